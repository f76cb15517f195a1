#!/usr/bin/env bash
# A planner process fails in the middle of a replanning run, and the run still reaches the goal:
#   kill: the contact planner is killed (SIGKILL); the supervisor restarts it after its back-off.
#   stop: the contact planner is stopped (SIGSTOP) and so falls silent; the supervisor names it,
#         kills it and restarts it.
# Meanwhile the robot holds its stance at the step boundary, waiting for a plan.
# Usage: tests/process_fault_test.sh kill|stop
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mode="${1:-}"
case "$mode" in
  kill) signal=KILL; expect="contact_planner \(pid [0-9]+\) died: killed by signal 9" ;;
  stop) signal=STOP; expect="contact_planner \(pid [0-9]+\) stopped answering: no STATUS for" ;;
  -h|--help) sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "process_fault_test: expected kill or stop, got '$mode'" >&2; exit 2 ;;
esac
scenario="$root/tests/data/flat_short.yaml"
dir="$(mktemp -d)"
launch_pid=""
cleanup() {
  [ -z "$launch_pid" ] || kill -TERM "$launch_pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT
RBCP_LOG_DIR="$dir" "$root/tools/netns-run" "$root/tools/launch" --scenario "$scenario" --timeout 60 >"$dir/launch.txt" 2>&1 &
launch_pid=$!

# Once the contact planner has answered two step boundaries, signal it.
pid=""
for _ in $(seq 1 600); do
  if [ -z "$pid" ]; then
    pid="$(sed -n 's/^\[supervisor\] contact_planner started (pid \([0-9]*\)).*/\1/p' "$dir/supervisor.log" 2>/dev/null | head -n 1 || true)"
  fi
  if [ -n "$pid" ] && grep -q "plan 2:" "$dir/contact_planner.log" 2>/dev/null; then break; fi
  kill -0 "$launch_pid" 2>/dev/null || break
  sleep 0.1
done
[ -n "$pid" ] || { cat "$dir/launch.txt"; echo "process_fault_test: the contact planner never started" >&2; exit 1; }
grep -q "plan 2:" "$dir/contact_planner.log" || { cat "$dir/launch.txt"; echo "process_fault_test: no second plan" >&2; exit 1; }
kill -"$signal" "$pid"
echo "process_fault_test: sent SIG$signal to contact_planner (pid $pid) after its second plan"
rc=0
wait "$launch_pid" || rc=$?
launch_pid=""
cat "$dir/launch.txt"
[ $rc -eq 0 ] || { echo "process_fault_test: tools/launch exited $rc" >&2; exit 1; }
grep -Eq "$expect" "$dir/launch.txt" || { echo "process_fault_test: the supervisor did not report: $expect" >&2; exit 1; }
grep -Eq "contact_planner restarted \(pid [0-9]+\)" "$dir/launch.txt" || { echo "process_fault_test: no restart reported" >&2; exit 1; }
grep -Eq "the robot reached the goal: goal reached" "$dir/launch.txt" || { echo "process_fault_test: the goal was not reached" >&2; exit 1; }
# Nothing is left running: every process the supervisor started ended with the run.
for p in $(sed -n 's/.*(pid \([0-9]*\)).*/\1/p' "$dir/supervisor.log" | sort -u); do
  if [ -d "/proc/$p" ] && ! grep -q '^State:.*Z' "/proc/$p/status" 2>/dev/null; then
    echo "process_fault_test: process $p of the run is still running: $(tr '\0' ' ' <"/proc/$p/cmdline")" >&2
    exit 1
  fi
done
echo "process_fault_test: after SIG$signal the contact planner was restarted and the robot reached the goal"
