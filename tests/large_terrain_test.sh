#!/usr/bin/env bash
# A terrain of 204,800 triangles end to end over LCM: a gently bumpy heightfield (0.5 m tiles
# 0 or 2 cm high, 1.25 cm grid, 4 m x 4 m) written as an OBJ mesh into a scenario, driven through
# the planner processes by tools/launch --no-sim inside a private network namespace. The terrain
# message is several MB, so it goes in parts on TERRAIN/PART; every process must have it whole:
# the affordance extractor answers with surfaces, the root planner with a path, the contact
# planner with a plan that passes the checker. Each supervised process's peak resident memory
# must stay under 1 GB. Prints the terrain's size, the extraction and planning times and the
# memory.
# Usage: tests/large_terrain_test.sh
set -euo pipefail
case "${1:-}" in
  -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  "") ;;
  *) echo "large_terrain_test: no arguments expected, got '$1'" >&2; exit 2 ;;
esac
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT

# The heightfield: (n + 1)^2 vertices, two counter-clockwise triangles per cell; vertex heights by
# 0.5 m tile (40 cells), so every tile is one flat region and the cells between tiles of different
# heights are steep steps.
n=320
awk -v n="$n" 'BEGIN {
  cell = 4.0 / n
  for (j = 0; j <= n; ++j) {
    tj = int(j / 40); if (tj > 7) tj = 7
    for (i = 0; i <= n; ++i) {
      ti = int(i / 40); if (ti > 7) ti = 7
      z = ((ti + 2 * tj) % 3 == 0) ? 0.02 : 0.0
      printf "v %.4f %.4f %.3f\n", -2.0 + i * cell, -2.0 + j * cell, z
    }
  }
  for (j = 0; j < n; ++j) {
    for (i = 0; i < n; ++i) {
      a = j * (n + 1) + i + 1; b = a + 1; d = a + n + 1; c = d + 1
      printf "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d
    }
  }
}' >"$dir/field.obj"
triangles="$(grep -c '^f ' "$dir/field.obj")"
[ "$triangles" -ge 200000 ] || { echo "large_terrain_test: the field has $triangles triangles, expected >= 200000" >&2; exit 1; }
cat >"$dir/large_terrain.yaml" <<'EOF'
name: large_terrain
terrain:
  - mesh: {file: field.obj, position: [0, 0, 0], rpy: [0, 0, 0], scale: 1.0}
start: {position: [-0.25, 0.25], yaw: 0}
goal: {position: [0.35, 0.25], yaw: 0}
EOF

rc=0
RBCP_LOG_DIR="$dir/logs" "$root/tools/netns-run" "$root/tools/launch" --no-sim --scenario "$dir/large_terrain.yaml" \
  --timeout 40 --time-budget 20 >"$dir/launch.txt" 2>&1 || rc=$?
cat "$dir/launch.txt"
fail() {
  echo "large_terrain_test: $1" >&2
  for f in "$dir"/logs/*.log; do echo "--- $(basename "$f"):" >&2; tail -n 15 "$f" >&2; done
  exit 1
}
[ $rc -eq 0 ] || fail "tools/launch exited $rc"
grep -Eq "terrain: $triangles triangles, [0-9.]+ MB on TERRAIN in [1-9][0-9]* parts" "$dir/launch.txt" \
  || fail "the terrain did not go in parts on TERRAIN/PART"
summary="$(grep -E '^summary: large_terrain: ' "$dir/launch.txt" || true)"
[[ "$summary" =~ summary:\ large_terrain:\ [1-9][0-9]*\ surfaces,\ root\ path\ of\ [0-9.]+\ s\ in\ [0-9.]+\ ms,\ [1-9][0-9]*\ contact\ steps\ in\ [0-9.]+\ ms,\ the\ plan\ passes\ the\ checker ]] \
  || fail "no surfaces, root path and checked contact plan on the large terrain"

# Peak resident memory of every supervised process, under 1 GB.
memory="$(sed -n 's/^launch: peak resident memory: //p' "$dir/launch.txt")"
[ -n "$memory" ] || fail "tools/launch printed no peak resident memory"
for p in affordance_extractor root_planner contact_planner; do
  mb="$(grep -Eo "$p [0-9.]+ MB" <<<"$memory" | grep -Eo '[0-9.]+' || true)"
  [ -n "$mb" ] || fail "no peak resident memory of $p"
  awk -v mb="$mb" 'BEGIN { exit !(mb < 1024) }' || fail "$p peaked at $mb MB, over 1 GB"
done
extraction="$(grep -Eo 'extracted in [0-9.]+ ms' "$dir/launch.txt" | head -n 1 || true)"
echo "large_terrain_test: $triangles triangles; $(grep -Eo '[0-9.]+ MB on TERRAIN in [0-9]+ parts' "$dir/launch.txt" | head -n 1);" \
  "${extraction:-extraction time not printed}; ${summary#summary: }; peak resident memory: $memory"
echo "large_terrain_test: every process received the whole terrain and the plan on it passes the checker"
