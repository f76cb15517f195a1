#!/usr/bin/env bash
# The replanning loop on the perceived terrain: the planners plan on the map terrain_mapper builds
# from the simulator's depth cameras, and the goal lies beyond what they see from the start. The
# robot walks to it (the simulator judges the walk on the true terrain), and run_log judges the map
# against the true terrain: height error, coverage of the walked path, cloud-to-TERRAIN latency;
# map_replay replays the log into a mapper of its own, which sends the same maps.
# (check_plan is not asked: the plans' footholds lie on the map's surfaces, a millimetre or so off
# the true ones, beyond the checker's tolerance for a plan made on the terrain it checks.)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
scenario="$root/tests/data/flat_far_goal.yaml"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
RBCP_LOG_DIR="$dir" "$root/tools/netns-run" "$root/tools/launch" --scenario "$scenario" --walk dynamic \
  --terrain perceived --timeout 30 | tee "$dir/launch.txt"
grep -Eq "the robot reached the goal: goal reached" "$dir/launch.txt" \
  || { echo "perceived_loop_test: the robot did not reach the goal" >&2; exit 1; }
grep -q "towards the goal, to (" "$dir/root_planner.log" \
  || { echo "perceived_loop_test: the first paths did not end short of the goal (is it beyond the cameras?)" >&2; exit 1; }
"$bin/run_log" --log "$dir/run.lcmlog" > "$dir/run.json"
python3 - "$dir/run.json" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))["perception"]
assert p is not None, "no perception in the run's JSON"
e = p["height_error_m"]
print(f"perceived_loop_test: {p['clouds']} clouds, {p['maps']} maps, {e['cells']} cells known: height error "
      f"{1000 * e['rms']:.1f} mm RMS, {1000 * e['p95']:.1f} mm p95; path coverage {p['path_coverage']:.2f}; "
      f"cloud to TERRAIN median {p['cloud_to_terrain_ms']['median']:.1f} ms")
assert e["cells"] > 1000 and e["rms"] <= 0.02, "the map is off the true terrain"
assert p["path_coverage"] >= 0.5, "the map does not cover the walked path"
assert p["cloud_to_terrain_ms"]["count"] > 0, "no map of a capture's time"
PY
# Exit status 3: a cloud was lost on the way (UDP under load); the maps before it must still match.
replay_status=0
"$bin/map_replay" --log "$dir/run.lcmlog" > "$dir/map_replay.txt" || replay_status=$?
cat "$dir/map_replay.txt"
{ [ "$replay_status" -eq 0 ] || [ "$replay_status" -eq 3 ]; } && grep -Eq "the replayed mapper sent the same [1-9]" "$dir/map_replay.txt" \
  || { echo "perceived_loop_test: the log replayed into a mapper gives other maps" >&2; exit 1; }
echo "perceived_loop_test: the robot walked to a goal beyond its cameras on the map it built"
