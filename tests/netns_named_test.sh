#!/usr/bin/env bash
# A named namespace joined by two separate invocations of tools/netns-run (as from two
# terminals): the affordance extractor started in one answers the scenario publisher run in the
# other; taking the namespace down stops what still runs in it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
if [ "$(id -u)" -ne 0 ] && ! sudo -n true 2>/dev/null; then
  echo "netns_named_test: skipped, named namespaces need root or sudo"; exit 77
fi
name="rbcp-test-$$"
log="$(mktemp)"
trap '"$root/tools/netns-run" --down "$name" >/dev/null 2>&1 || true; rm -f "$log"' EXIT
"$root/tools/netns-run" --name "$name" true
"$root/tools/netns-run" --name "$name" "$bin/affordance_extractor" --max-runtime 120 >"$log" 2>&1 &
"$root/tools/netns-run" --name "$name" "$bin/scenario_publisher" --scenario "$root/tests/data/flat_short.yaml" \
  --until affordance --timeout 30
"$root/tools/netns-run" --down "$name"
wait
echo "netns_named_test: two invocations shared the namespace '$name'"
