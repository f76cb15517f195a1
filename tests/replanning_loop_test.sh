#!/usr/bin/env bash
# The replanning loop end to end: tools/launch walks the robot to the goal of a short scenario,
# recording every channel; run_log turns the log into JSON, whose walked plan passes check_plan.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
scenario="$root/tests/data/flat_short.yaml"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
RBCP_LOG_DIR="$dir" "$root/tools/netns-run" "$root/tools/launch" --scenario "$scenario" --timeout 30 | tee "$dir/launch.txt"
grep -Eq "the robot reached the goal: goal reached.*[1-9][0-9]* plans \(0 failed replans\), .*replanning latency median" "$dir/launch.txt" \
  || { echo "replanning_loop_test: no successful loop summary" >&2; exit 1; }
"$bin/run_log" --log "$dir/run.lcmlog" > "$dir/run.json"
for key in '"sim_ok":true' '"scenario":"flat_short"' '"unanswered_waits":0' '"sim_trace":\[\{' '"schema_version":1' '"replans":\[\{' '"torques":\[' '"contact_surfaces":\[\{'; do
  grep -Eq "$key" "$dir/run.json" || { echo "replanning_loop_test: run_log JSON lacks $key" >&2; exit 1; }
done
grep -Eq '"plans":[1-9]' "$dir/run.json" || { echo "replanning_loop_test: no plan in the log" >&2; exit 1; }
# The log holds every plan the operator heard: a recorder that drops messages under load loses some.
heard="$(grep -Eo '[0-9]+ plans \(' "$dir/launch.txt" | grep -Eo '^[0-9]+')"
logged="$(grep -Eo '"plans":[0-9]+' "$dir/run.json" | grep -Eo '[0-9]+$')"
[ "$heard" = "$logged" ] || { echo "replanning_loop_test: the operator heard $heard plans, the log holds $logged" >&2; exit 1; }
"$bin/check_plan" --scenario "$scenario" --plan "$dir/run.json"
echo "replanning_loop_test: the walked plan of the logged run passes the checker"
