#!/usr/bin/env bash
# The world changes while the robot walks (anymal_sim --events): the terrain is republished, the
# surfaces re-extracted, the root path and the contact plans redone around the change, and the
# robot still reaches the goal.
# Usage: tests/world_event_test.sh SCENARIO.yaml EVENTS.yaml
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case "${1:-}" in -h|--help) sed -n '2,5p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
[ $# -eq 2 ] && [ -f "$1" ] && [ -f "$2" ] || { echo "world_event_test: expected a scenario and an events file" >&2; exit 2; }
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
rc=0
RBCP_LOG_DIR="$dir" "$root/tools/netns-run" "$root/tools/launch" --scenario "$1" --events "$2" --timeout 60 \
  >"$dir/launch.txt" 2>&1 || rc=$?
cat "$dir/launch.txt"
[ $rc -eq 0 ] || { echo "world_event_test: tools/launch exited $rc" >&2; exit 1; }
grep -q "event at .*: add box" "$dir/anymal_sim.log" || { echo "world_event_test: the simulator applied no event" >&2; exit 1; }
grep -q "replanned from the measured base: the terrain changed" "$dir/root_planner.log" \
  || { echo "world_event_test: the root planner did not replan on the new terrain" >&2; exit 1; }
# The walked plan passes the checker on the world as it was at the end (with the box).
"$bin/run_log" --log "$dir/run.lcmlog" >"$dir/run.json"
grep -q '"sim_ok":true' "$dir/run.json" || { echo "world_event_test: the log's verdict is not a success" >&2; exit 1; }
echo "world_event_test: the world changed and the robot reached the goal"
