#!/usr/bin/env bash
# A lossy, disordered link: every process of a replanning run drops, duplicates and reorders the
# messages it receives (RBCP_MESSAGE_FAULTS), and the robot still reaches the goal: stale and
# superseded plans are dropped, a lost plan is sent again, lost states and terrains come again.
# The plan the robot walked, as the log recorded it, passes the checker.
# Usage: tests/message_fault_test.sh [FAULTS]   (default drop=0.2,duplicate=0.2,reorder=0.2,seed=1)
set -euo pipefail
case "${1:-}" in
  -h|--help) sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
esac
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
faults="${1:-drop=0.2,duplicate=0.2,reorder=0.2,seed=1}"
scenario="$root/tests/data/flat_short.yaml"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
rc=0
RBCP_MESSAGE_FAULTS="$faults" RBCP_LOG_DIR="$dir" "$root/tools/netns-run" "$root/tools/launch" --scenario "$scenario" \
  --timeout 120 >"$dir/launch.txt" 2>&1 || rc=$?
cat "$dir/launch.txt"
[ $rc -eq 0 ] || { echo "message_fault_test: tools/launch exited $rc" >&2; tail -n 30 "$dir"/*.log >&2; exit 1; }
grep -Eq "the robot reached the goal: goal reached" "$dir/launch.txt" || { echo "message_fault_test: the goal was not reached" >&2; exit 1; }
# Every process ran with the faults.
for p in anymal_sim affordance_extractor root_planner contact_planner; do
  grep -q "RBCP_MESSAGE_FAULTS: received messages dropped" "$dir/$p.log" \
    || { echo "message_fault_test: $p did not run with the message faults" >&2; exit 1; }
done
if grep -q "rejected CONTACT_PLAN" "$dir"/*.log; then echo "message_fault_test: a plan was rejected" >&2; exit 1; fi
"$bin/run_log" --log "$dir/run.lcmlog" > "$dir/run.json"
"$bin/check_plan" --scenario "$scenario" --plan "$dir/run.json"
stale="$(grep -c "dropped stale CONTACT_PLAN" "$dir/anymal_sim.log" || true)"
resent="$(grep -c "sent again" "$dir/contact_planner.log" || true)"
echo "message_fault_test: with $faults the robot reached the goal ($stale stale plans dropped, $resent plans sent again) and the walked plan passes the checker"
