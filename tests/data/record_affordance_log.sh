#!/usr/bin/env bash
# Records tests/data/affordances_darpa_rubble.lcmlog from a real run: lcm-logger captures
# TERRAIN and AFFORDANCES while scenario_publisher drives affordance_extractor. Re-record after
# an intended change of the extraction's output. Usage: tests/data/record_affordance_log.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
if [ "${RBCP_NETNS:-}" != "1" ]; then exec "$root/tools/netns-run" "$0" "$@"; fi
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
out="$root/tests/data/affordances_darpa_rubble.lcmlog"
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=2097152"
rm -f "$out"
lcm-logger --lcm-url="$url" --channel="TERRAIN(/PART)?|AFFORDANCES(/PART)?" --quiet --force "$out" &
logger=$!
"$bin/affordance_extractor" --lcm-url "$url" --quiet &
extractor=$!
sleep 0.5
kill -0 "$logger" "$extractor" || { echo "record: lcm-logger or affordance_extractor did not start" >&2; exit 1; }
"$bin/scenario_publisher" --lcm-url "$url" --scenario "$root/config/scenarios/darpa_rubble.yaml" --until affordance >/dev/null
sleep 0.5
kill -INT "$logger" "$extractor"
wait "$logger" "$extractor" || true
echo "recorded $out ($(stat -c %s "$out") bytes)"
