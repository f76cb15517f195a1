#!/usr/bin/env bash
# Soak: one running pipeline (affordance_extractor, root_planner and contact_planner under the
# supervisor) answers RUNS operator runs in a row over a link on which every process loses a
# share of the messages it receives (RBCP_MESSAGE_FAULTS). The runs cycle through five runs of
# small scenarios on three terrains: a short walk twice in a row, a turn on the spot, an island
# the goal cannot be reached from (its correct answer is goal_unreachable) and a longer walk.
# Every run must get
# its own correct answer; no process may die, and none may end above 300 MB resident.
# Usage: tests/soak_test.sh [RUNS] [DROP]   (default 20 runs, drop=0.05)
set -euo pipefail
case "${1:-}" in
  -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
esac
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
runs="${1:-20}"
drop="${2:-0.05}"
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "soak_test: RUNS expects a positive count, got '$runs'" >&2; exit 2; }
if [ "${RBCP_NETNS:-}" != "1" ]; then exec "$root/tools/netns-run" "$0" "$runs" "$drop"; fi
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=2097152"
dir="$(mktemp -d)"
supervisor_pid=""
cleanup() {
  if [ -n "$supervisor_pid" ]; then kill -TERM "$supervisor_pid" 2>/dev/null || true; wait "$supervisor_pid" 2>/dev/null || true; fi
  rm -rf "$dir"
}
trap cleanup EXIT
export RBCP_MESSAGE_FAULTS="drop=$drop,seed=7"

{
  echo "heartbeat_timeout_s: 2.0"
  echo "startup_timeout_s: 60.0"
  echo "backoff_initial_s: 0.5"
  echo "backoff_max_s: 8.0"
  echo "healthy_after_s: 30.0"
  echo "max_restarts: 10"
  echo "stop_grace_s: 3.0"
  echo "processes:"
  for p in affordance_extractor root_planner contact_planner; do
    echo "  - {name: $p, command: ['$bin/$p', --lcm-url, '$url'], log: '$dir/$p.log'}"
  done
} >"$dir/processes.yaml"
"$bin/supervisor" --lcm-url "$url" --spec "$dir/processes.yaml" >"$dir/supervisor.log" 2>&1 &
supervisor_pid=$!

scenarios=(flat_short flat_short turn_on_the_spot island_unreachable flat_walk)
failed=0
start=$SECONDS
for i in $(seq 1 "$runs"); do
  name="${scenarios[$(((i - 1) % ${#scenarios[@]}))]}"
  rc=0
  "$bin/scenario_publisher" --lcm-url "$url" --scenario "$root/tests/data/$name.yaml" --until contact --timeout 60 \
    >"$dir/run$i.txt" 2>&1 || rc=$?
  summary="$(grep '^summary:' "$dir/run$i.txt" | tail -n 1 || true)"
  if [ "$name" = island_unreachable ]; then
    ok=0; [ $rc -eq 1 ] && grep -q "root planning failed: root_planner: goal_unreachable" "$dir/run$i.txt" && ok=1
  else
    ok=0; [ $rc -eq 0 ] && grep -q "the plan passes the checker" "$dir/run$i.txt" && ok=1
  fi
  if [ $ok -eq 1 ]; then
    echo "soak_test: run $i ($name): answered correctly: ${summary#summary: }"
  else
    echo "soak_test: run $i ($name): WRONG ANSWER (exit $rc):" >&2
    cat "$dir/run$i.txt" >&2
    failed=$((failed + 1))
  fi
done
elapsed=$((SECONDS - start))

kill -TERM "$supervisor_pid"
wait "$supervisor_pid" || true
supervisor_pid=""
cat "$dir/supervisor.log"
if grep -E "died|stopped answering|restart" "$dir/supervisor.log" | grep -vq "restarts: none"; then
  echo "soak_test: a process died or was restarted" >&2
  failed=$((failed + 1))
fi
# "peak resident memory: affordance_extractor 10.0 MB, root_planner 19.5 MB, ..."
peaks="$(grep -o "peak resident memory: .*" "$dir/supervisor.log" | tail -n 1)"
[ -n "$peaks" ] || { echo "soak_test: the supervisor reported no memory" >&2; failed=$((failed + 1)); }
while read -r process mb; do
  if awk -v m="$mb" 'BEGIN { exit !(m > 300) }'; then
    echo "soak_test: $process ended at $mb MB resident, above 300 MB" >&2
    failed=$((failed + 1))
  fi
done < <(echo "${peaks#peak resident memory: }" | tr ',' '\n' | sed -E 's/^ *([a-z_]+) ([0-9.]+) MB.*/\1 \2/')
[ $failed -eq 0 ] || { echo "soak_test: $failed problems in $runs runs" >&2; exit 1; }
echo "soak_test: $runs runs in a row with drop=$drop answered correctly in ${elapsed} s; no process died; $peaks"
