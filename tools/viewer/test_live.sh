#!/usr/bin/env bash
# The live viewer end to end, in a private network namespace: tools/launch walks the robot on a
# short scenario on the wall clock while two live_bridge processes forward it, one subscribed to
# LCM (serving the live page over HTTP), one following the run's growing LCM log (the page opened
# from disk, as tools/demo --live does). Headless Chromium checks that each page receives the run
# and follows the robot, draws the terrain and the footholds (on the screenshot's pixels), logs no
# console error and talks to nothing but its bridge. Then the page of the recorded log (tools/view
# LOG) must show the run with its plots (torques, CoM margin, replanning latency).
# Outputs go to $RBCP_BUILD_DIR/view_test/live (default build/view_test/live).
# Usage: tools/viewer/test_live.sh   (no arguments; exit status 0 passed, 1 failed, 2 bad arguments)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build_dir="${RBCP_BUILD_DIR:-$root/build}"
bin="$build_dir/bin"
out="$build_dir/view_test/live"
check_page() { node "$root/tools/viewer/check_page.mjs" "$@" 2> >(grep -v 'unexpected operator' >&2); }

case "${1:-}" in
  -h|--help) sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  "") ;;
  --inside) ;;
  *) echo "test_live: takes no arguments, got '$1'" >&2; exit 2 ;;
esac

if [ "${1:-}" != "--inside" ]; then
  # Outside the namespace (which has no route to the package registries): install and build.
  "$root/tools/viewer/install_chromium"
  "$root/tools/setup"
  mkdir -p "$out"
  "$root/tools/build" live_bridge scene_json run_log anymal_sim affordance_extractor root_planner contact_planner \
    scenario_publisher >"$out/build.log" 2>&1 || { cat "$out/build.log"; exit 1; }
  # Written for port 8765; the test opens it with ?ws= for the bridges' own ports.
  "$root/tools/view" --live -o "$out/live.html"
  exec "$root/tools/netns-run" "$0" --inside
fi

rm -rf "$out/run"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT

port_of() {  # port_of LOGFILE: the port a live_bridge prints once it listens
  local i
  for i in $(seq 1 100); do
    if grep -q "listening on" "$1" 2>/dev/null; then sed -n 's/.*listening on http:\/\/127.0.0.1:\([0-9]*\)\/.*/\1/p' "$1"; return 0; fi
    sleep 0.1
  done
  echo "test_live: live_bridge did not start:" >&2; cat "$1" >&2; return 1
}

"$bin/live_bridge" --port 0 --page "$out/live.html" --quiet 2>"$out/bridge_lcm.log" &
pids+=($!)
mkdir -p "$out/run"
"$bin/live_bridge" --port 0 --follow-log "$out/run/run.lcmlog" --quiet 2>"$out/bridge_log.log" &
pids+=($!)
lcm_port="$(port_of "$out/bridge_lcm.log")"
log_port="$(port_of "$out/bridge_log.log")"
RBCP_LOG_DIR="$out/run" "$root/tools/launch" --scenario "$root/tests/data/flat_short.yaml" --realtime --timeout 60 \
  >"$out/launch.txt" 2>&1 &
launch=$!

# Both pages at once, while the robot walks.
check_page --url "http://127.0.0.1:$lcm_port/" --live --allow-host "127.0.0.1:$lcm_port" \
  --screenshot "$out/live_lcm.png" --expect-plot "joint torques" --expect-plot "CoM margin" >"$out/check_lcm.txt" 2>&1 &
check_lcm=$!
check_page --url "file://$out/live.html?ws=ws://127.0.0.1:$log_port/ws" --live --allow-host "127.0.0.1:$log_port" \
  --screenshot "$out/live_log.png" >"$out/check_log.txt" 2>&1 &
check_log=$!
passed=0 failed=0
for check in "live page served by the LCM bridge:$check_lcm:check_lcm" "live page from disk, bridge following the run's log:$check_log:check_log"; do
  IFS=: read -r name pid file <<<"$check"
  echo "== $name"
  rc=0; wait "$pid" || rc=$?
  cat "$out/$file.txt"
  if [ $rc -eq 0 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
done

rc=0
wait "$launch" || rc=$?
cat "$out/launch.txt"
if [ $rc -ne 0 ]; then
  echo "test_live: tools/launch exited $rc"
  failed=$((failed + 1))
else
  echo "== the page of the run's log (tools/view LOG)"
  if "$root/tools/view" "$out/run/run.lcmlog" -o "$out/run.html" &&
     check_page --page "$out/run.html" --screenshot "$out/run.png" --expect-status "run reached the goal" \
       --expect-plot "joint torques" --expect-plot "CoM margin" --expect-plot "replanning latency" \
       --expect-plot "step timeline"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
  fi
fi
echo "screenshots: $out/live_lcm.png $out/live_log.png $out/run.png"
echo "test_live: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
