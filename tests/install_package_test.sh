#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then: the installed programs find their config in the
# prefix (not the source tree), and a project outside the source tree (tests/install_consumer)
# builds with find_package(rbcp), links rbcp::contact_planner and plans footsteps.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${RBCP_BUILD_DIR:-$root/build}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"

cmake --install "$build_dir" --prefix "$prefix" >"$work/install.log"
echo "install_package_test: installed $(grep -c 'Installing' "$work/install.log") files into the prefix"
for f in bin/plan_scenario bin/anymal_sim bin/live_bridge bin/terrain_mapper share/rbcp/config/robots/anymal_b.urdf share/rbcp/config/mapper.yaml \
         include/rbcp/contact_planner/contact_planner.h lib/cmake/rbcp/rbcpConfig.cmake; do
  [ -e "$prefix/$f" ] || { echo "install_package_test: FAILED: $f is not installed" >&2; exit 1; }
done

# The installed programs read the prefix's config: copied elsewhere (no source tree near it),
# plan_scenario's default config folder is the prefix's, and a root path is planned with it.
cp -r "$prefix" "$work/moved"
help="$(cd / && env -u RBCP_CONFIG_DIR "$work/moved/bin/plan_scenario" --help)"
grep -q -- "--config-dir TEXT=$work/moved/share/rbcp/config\b" <<<"$help" \
  || { echo "install_package_test: FAILED: plan_scenario's default config is not the prefix's:" >&2; grep -- --config-dir <<<"$help" >&2; exit 1; }
(cd / && env -u RBCP_CONFIG_DIR "$work/moved/bin/plan_scenario" --stage root --json --quiet \
   --scenario "$work/moved/share/rbcp/config/scenarios/flat_ground.yaml") >"$work/root.json"
grep -q '"root_ok":true' "$work/root.json" || { echo "install_package_test: FAILED: the installed plan_scenario planned no root path" >&2; exit 1; }
echo "install_package_test: the installed plan_scenario, moved, plans with its own config"

# An outside project against the package.
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cp -r "$root/tests/install_consumer" "$work/consumer"
# Libraries built with the sanitizers (tools/test --sanitize) need their runtimes in the program.
sanitize=()
if grep -q '^RBCP_SANITIZE:BOOL=ON' "$build_dir/CMakeCache.txt" 2>/dev/null; then
  sanitize=(-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined)
fi
cmake -S "$work/consumer" -B "$work/consumer/build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" "${sanitize[@]}" >"$work/consumer.log" 2>&1 || { cat "$work/consumer.log"; echo "install_package_test: FAILED: configuring the outside project" >&2; exit 1; }
cmake --build "$work/consumer/build" >>"$work/consumer.log" 2>&1 || { cat "$work/consumer.log"; echo "install_package_test: FAILED: building the outside project" >&2; exit 1; }
"$work/consumer/build/plan_steps"
echo "install_package_test: an outside project built with find_package(rbcp) and ran rbcp::contact_planner"
