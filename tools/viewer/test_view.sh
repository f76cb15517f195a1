#!/usr/bin/env bash
# End-to-end check of tools/view in headless Chromium: plans a short walk on flat ground
# (tests/data/flat_short.yaml: contact stage, and sim stage: a few seconds simulated), writes
# the viewer pages, loads each from disk and checks that it made no network request, logged no
# console error, drew with WebGL, and that its screenshot shows the terrain and the footholds in
# the leg colours; the run's page has its plots (torques, CoM margin, step timeline); a page of a
# failed plan must show the failure text. The same walk in the dynamic walk (controller.mode:
# dynamic) shows its CoM and ZMP references, the support polygon and the centre of pressure; a
# trace without those fields (an older run's) loads as before. A run on the mapped terrain
# (tests/data/flat_short_perceived_run.json: run_log's JSON of `tools/launch --scenario
# tests/data/flat_short.yaml --walk dynamic --terrain perceived`, cropped by
# tools/viewer/crop_run.mjs) shows its elevation map, the true terrain and the map's metrics;
# the runs on the true terrain have none of these.
# Installs Debian's chromium when it is missing (as root, or with sudo).
# Outputs (pages, screenshots) go to $RBCP_BUILD_DIR/view_test (default build/view_test).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build_dir="${RBCP_BUILD_DIR:-$root/build}"
out="$build_dir/view_test"

case "${1:-}" in
  -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; echo "Usage: tools/viewer/test_view.sh (no arguments; exit status 0 passed, 1 failed, 2 bad arguments)"; exit 0 ;;
  "") ;;
  *) echo "test_view: takes no arguments, got '$1'" >&2; exit 2 ;;
esac

"$root/tools/viewer/install_chromium"
mkdir -p "$out"
"$root/tools/setup"
"$root/tools/build" plan_scenario scene_json >"$out/build.log" 2>&1 || { cat "$out/build.log"; exit 1; }

scenario="$root/tests/data/flat_short.yaml"
"$build_dir/bin/plan_scenario" --scenario "$scenario" --stage contact --json >"$out/flat_contact.json"
# The sim stage exits 1 when the simulated run fails; its page must show that run all the same.
rc=0
"$build_dir/bin/plan_scenario" --scenario "$scenario" --stage sim --json >"$out/flat_sim.json" || rc=$?
[ "$rc" -le 1 ] || { echo "test_view: plan_scenario --stage sim exited $rc"; exit 1; }
# A plan that failed at the contact stage: no states, a failure text.
node -e '
  const fs = require("fs");
  const run = JSON.parse(fs.readFileSync(process.argv[1], "utf8"));
  Object.assign(run, { contact_ok: false, contact_status: "failed", steps: 0, states: [],
                       failure: "contact: test failure <no foothold>" });
  fs.writeFileSync(process.argv[2], JSON.stringify(run));' "$out/flat_contact.json" "$out/flat_failed.json"
# The dynamic walk: the shipped configuration with controller.mode dynamic.
rm -rf "$out/config_dynamic"
cp -r "$root/config" "$out/config_dynamic"
sed -i 's/^mode: static$/mode: dynamic/' "$out/config_dynamic/controller.yaml"
grep -q '^mode: dynamic$' "$out/config_dynamic/controller.yaml" || { echo "test_view: controller.yaml has no 'mode: static' line"; exit 1; }
"$build_dir/bin/plan_scenario" --scenario "$scenario" --stage sim --json --config-dir "$out/config_dynamic" \
  >"$out/flat_dynamic.json" || { echo "test_view: the dynamic walk failed"; exit 1; }
# A trace from before the simulator recorded references and the centre of pressure.
node -e '
  const fs = require("fs");
  const run = JSON.parse(fs.readFileSync(process.argv[1], "utf8"));
  for (const s of run.sim_trace) for (const key of ["com_reference", "zmp_reference", "cop"]) delete s[key];
  fs.writeFileSync(process.argv[2], JSON.stringify(run));' "$out/flat_sim.json" "$out/flat_sim_old.json"
cp "$root/tests/data/flat_short_perceived_run.json" "$out/flat_perceived.json"

passed=0 failed=0
view_args=(--scenario "$scenario")  # a run's log brings its own terrain: view_args=()
check() {  # check NAME [check_page options...]
  local name="$1"
  shift
  echo "== $name"
  if "$root/tools/view" "$out/$name.json" "${view_args[@]}" -o "$out/$name.html" &&
     node "$root/tools/viewer/check_page.mjs" --page "$out/$name.html" --screenshot "$out/$name.png" "$@" \
       2> >(grep -v 'unexpected operator' >&2); then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
  fi
}
check flat_contact --expect-status "contact plan"
check flat_sim --expect-plot "joint torques" --expect-plot "CoM margin" --expect-plot "step timeline" \
  --expect-plot "CoP margin" --expect-layer support --no-layer references --no-layer elevation --no-layer truth
check flat_failed --no-footholds --expect-status "failure: contact: test failure <no foothold>"
check flat_dynamic --expect-plot "CoP margin" --expect-layer references --expect-layer support \
  --expect-legend "CoM reference" --expect-legend "ZMP reference" --expect-legend "centre of pressure"
check flat_sim_old --expect-plot "CoM margin" --no-layer references --no-layer support
view_args=()
check flat_perceived --expect-layer elevation --expect-layer truth --expect-legend "elevation map" \
  --expect-perception "RMS 1.6 mm" --expect-perception "100.0 % of the walked path"

echo "screenshots: $out/flat_contact.png $out/flat_sim.png $out/flat_failed.png $out/flat_dynamic.png $out/flat_sim_old.png $out/flat_perceived.png"
echo "test_view: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
