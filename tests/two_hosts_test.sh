#!/usr/bin/env bash
# The pipeline split over two hosts (tools/launch-hosts: two network namespaces joined by a veth
# pair, LCM multicast with ttl=1 across it) on a short scenario:
#   run:       the robot reaches the goal; every process of each host's supervisor ran in that
#              host's namespace (ip netns identify), the operator's recording holds the robot's
#              verdict, and nothing is left behind (namespaces, veth, processes).
#   interrupt: SIGINT (Ctrl-C) to tools/launch-hosts once the robot walks: it exits 130 and
#              leaves nothing behind either.
# Usage: tests/two_hosts_test.sh run|interrupt   (needs root or sudo -n; exit 77: skipped without)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
mode="${1:-}"
case "$mode" in
  run|interrupt) ;;
  -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "two_hosts_test: expected run or interrupt, got '$mode'" >&2; exit 2 ;;
esac
if [ "$(id -u)" -ne 0 ]; then
  sudo -n true 2>/dev/null || { echo "two_hosts_test: skipped, network namespaces need root or sudo -n"; exit 77; }
  as_root=(sudo -n)
else
  as_root=()
fi
fail() { echo "two_hosts_test: $*" >&2; [ ! -f "$dir/hosts.txt" ] || sed 's/^/    /' "$dir/hosts.txt" >&2; exit 1; }
dir="$(mktemp -d)"
hosts_pid=""
cleanup() {
  [ -z "$hosts_pid" ] || kill -TERM "$hosts_pid" 2>/dev/null || true
  [ -z "$hosts_pid" ] || wait "$hosts_pid" 2>/dev/null || true
  "${as_root[@]}" rm -rf "$dir"
}
trap cleanup EXIT

# interrupt: on the wall clock, so that the walk (13 s) is still on when SIGINT comes. SIGINT at its
# default: a background job of a script would ignore it, a terminal's does not.
extra=()
[ "$mode" = run ] || extra=(--realtime)
RBCP_LOG_DIR="$dir" env --default-signal=INT "$root/tools/launch-hosts" \
  --scenario "$root/tests/data/flat_short.yaml" --timeout 60 "${extra[@]}" >"$dir/hosts.txt" 2>&1 &
hosts_pid=$!

# Once the contact planner has sent its first plan, every process of both hosts runs.
for _ in $(seq 1 900); do
  grep -q "plan 1:" "$dir/contact_planner.log" 2>/dev/null && break
  kill -0 "$hosts_pid" 2>/dev/null || break
  sleep 0.1
done
grep -q "plan 1:" "$dir/contact_planner.log" 2>/dev/null || fail "the contact planner sent no plan"
ns_robot="$(sed -n 's/^launch-hosts: robot: network namespace \([^,]*\),.* on \(.*\)$/\1/p' "$dir/hosts.txt")"
ns_operator="$(sed -n 's/^launch-hosts: operator: network namespace \([^,]*\),.* on \(.*\)$/\1/p' "$dir/hosts.txt")"
links="$(sed -n 's/^launch-hosts: [a-z]*: network namespace .* on \(.*\)$/\1/p' "$dir/hosts.txt")"
[ -n "$ns_robot" ] && [ -n "$ns_operator" ] && [ "$ns_robot" != "$ns_operator" ] || fail "no two namespaces named"
[ "$(wc -w <<<"$links")" -eq 2 ] || fail "no veth pair named"

# Each host's processes, as its supervisor started them, in that host's namespace.
pids_of() {  # pids_of HOST: the pids supervisor@HOST started, and its own
  sed -n 's/^\[supervisor@'"$1"'\] [a-z_]* started (pid \([0-9]*\)).*/\1/p' "$dir/supervisor-$1.log"
  sed -n 's/^launch@'"$1"': supervisor (pid \([0-9]*\)).*/\1/p' "$dir/launch-robot.txt" "$dir/hosts.txt"
}
all_pids=()
for host in robot operator; do
  ns="$ns_robot"; [ $host = robot ] || ns="$ns_operator"
  expected=2  # anymal_sim and contact_planner, or affordance_extractor and root_planner
  started="$(grep -c "^\[supervisor@$host\] [a-z_]* started (pid" "$dir/supervisor-$host.log" || true)"
  [ "$started" -eq $expected ] || fail "supervisor@$host started $started processes, expected $expected"
  mapfile -t pids < <(pids_of $host)
  [ ${#pids[@]} -eq $((expected + 1)) ] || fail "found ${#pids[@]} pids of the $host's side, expected $((expected + 1))"
  for p in "${pids[@]}"; do
    got="$("${as_root[@]}" ip netns identify "$p" 2>&1)" || fail "ip netns identify $p: $got"
    [ "$got" = "$ns" ] || fail "pid $p ($(tr '\0' ' ' <"/proc/$p/cmdline")) of the $host's side runs in '$got', not $ns"
  done
  echo "two_hosts_test: $host: pids ${pids[*]} run in $ns"
  all_pids+=("${pids[@]}")
done

rc=0
if [ "$mode" = interrupt ]; then
  kill -INT "$hosts_pid"
  wait "$hosts_pid" || rc=$?
  hosts_pid=""
  [ $rc -eq 130 ] || fail "tools/launch-hosts exited $rc after SIGINT, expected 130"
  grep -q "launch-hosts: interrupted: stopping both hosts" "$dir/hosts.txt" || fail "the interruption was not reported"
else
  wait "$hosts_pid" || rc=$?
  hosts_pid=""
  [ $rc -eq 0 ] || fail "tools/launch-hosts exited $rc"
  grep -Eq "the robot reached the goal: goal reached.*[1-9][0-9]* plans" "$dir/hosts.txt" || fail "the goal was not reached"
  grep -q "launch-hosts: both hosts stopped" "$dir/hosts.txt" || fail "no orderly stop"
  # The operator recorded what the robot said across the link: its verdict.
  "$bin/run_log" --log "$dir/run.lcmlog" >"$dir/run.json"
  grep -q '"sim_ok":true' "$dir/run.json" \
    || fail "the operator's recording lacks the simulator's verdict (run_log: $(grep -o '"outcome":"[^"]*"' "$dir/run.json" || true))"
fi
cat "$dir/hosts.txt"

# Nothing left behind: no process of the run, no namespace, no veth.
! grep -q "still running in" "$dir/hosts.txt" || fail "tools/launch-hosts had to kill leftovers"
for p in "${all_pids[@]}"; do
  if [ -d "/proc/$p" ] && ! grep -q '^State:.*Z' "/proc/$p/status" 2>/dev/null; then
    fail "process $p of the run is still running: $(tr '\0' ' ' <"/proc/$p/cmdline")"
  fi
done
for ns in "$ns_robot" "$ns_operator"; do
  ! "${as_root[@]}" ip netns list | grep -qw "^$ns" || fail "the namespace $ns is still there"
done
for link in $links; do
  ! ip -o link show | grep -q ": $link[@:]" || fail "the veth $link is still there"
done
echo "two_hosts_test: $mode: the two hosts ran in their own namespaces and left nothing behind"
