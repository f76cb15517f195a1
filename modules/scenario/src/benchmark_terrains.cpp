#include "rbcp/scenario/benchmark_terrains.h"

#include <array>
#include <cmath>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"

namespace rbcp {
namespace {

// Every untilted box reaches down to this depth [m]; floors are 0.5 m thick slabs with their top at z = 0.
constexpr double kBottomZ = -0.5;

// Cinder blocks: a 0.30 (x) by 0.21 (y) top tilted 15 deg, on a 0.30 m deep body.
constexpr double kBlockTopX = 0.30;
constexpr double kBlockTopY = 0.21;
constexpr double kBlockDepth = 0.30;
const double kBlockTilt = 15.0 * M_PI / 180.0;

TerrainBox Slab(double x0, double x1, double y0, double y1, double z_top) {
  TerrainBox box;
  box.size = Eigen::Vector3d(x1 - x0, y1 - y0, z_top - kBottomZ);
  box.position = Eigen::Vector3d(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z_top + kBottomZ));
  box.rpy = Eigen::Vector3d::Zero();
  return box;
}

/// The direction the top face of a block leans toward (its normal tilts that way, so the top
/// descends toward it).
enum class Tilt { kPlusX = 0, kPlusY = 1, kMinusX = 2, kMinusY = 3 };

bool IsPitched(Tilt tilt) { return tilt == Tilt::kPlusX || tilt == Tilt::kMinusX; }

/// A block whose top face is centred at top_centre [m].
TerrainBox TiltedBlock(const Eigen::Vector3d& top_centre, Tilt tilt) {
  TerrainBox box;
  box.size = Eigen::Vector3d(kBlockTopX, kBlockTopY, kBlockDepth);
  switch (tilt) {
    case Tilt::kPlusX: box.rpy = Eigen::Vector3d(0.0, kBlockTilt, 0.0); break;
    case Tilt::kMinusX: box.rpy = Eigen::Vector3d(0.0, -kBlockTilt, 0.0); break;
    case Tilt::kPlusY: box.rpy = Eigen::Vector3d(-kBlockTilt, 0.0, 0.0); break;
    case Tilt::kMinusY: box.rpy = Eigen::Vector3d(kBlockTilt, 0.0, 0.0); break;
  }
  box.position = top_centre - RotationFromRpy(box.rpy) * Eigen::Vector3d(0.0, 0.0, 0.5 * kBlockDepth);
  return box;
}

/// A 4 x 4 field of tilted blocks. The lean direction turns a quarter turn from one block to the
/// next along rows and columns ((column + row) mod 4 over +x, +y, -x, -y), so neighbours always
/// alternate between x and y tilts. The side below a block's high edge leans outward (by up to
/// depth * sin(15 deg) at the bottom); column and row spacings leave 1.4-2.5 cm between tops so
/// that this lean stays below the neighbouring tops (BenchmarkScenarioText checks it).
template <typename HeightFn>
void AddBlockField(std::vector<TerrainElement>& terrain, const std::array<double, 4>& column_x,
                   const std::array<double, 4>& row_y, HeightFn top_centre_z) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      const auto tilt = static_cast<Tilt>((c + r) % 4);
      const double z = top_centre_z(c, r, IsPitched(tilt));
      terrain.emplace_back(TiltedBlock(
          Eigen::Vector3d(column_x[static_cast<std::size_t>(c)], row_y[static_cast<std::size_t>(r)], z), tilt));
    }
  }
}

BaseGoal Pose(double x, double y) {
  BaseGoal g;
  g.position = Eigen::Vector2d(x, y);
  g.yaw = 0.0;
  return g;
}

BenchmarkScenario FlatGround() {
  BenchmarkScenario b;
  b.description = "flat ground: one 8.5 x 3 m floor with its top at z = 0; walk 5 m straight ahead";
  Scenario& s = b.scenario;
  s.name = "flat_ground";
  s.terrain.emplace_back(Slab(-1.75, 6.75, -1.5, 1.5, 0.0));
  s.start = Pose(0.0, 0.0);
  s.goal = Pose(5.0, 0.0);
  return b;
}

BenchmarkScenario SlalomDebris() {
  BenchmarkScenario b;
  b.description =
      "slalom debris: a 1 m corridor closed by an L of 0.908 m walls; the detour crosses a side lane of "
      "16 sunk blocks tilted 15 deg and a flat plank";
  Scenario& s = b.scenario;
  s.name = "slalom_debris";
  auto& t = s.terrain;
  // Main corridor y [-0.5, 0.5], cut by wall A; wall B runs along the corridor's left edge.
  t.emplace_back(Slab(-2.0, 0.522, -0.5, 0.5, 0.0));
  t.emplace_back(Slab(0.522, 0.542, -0.5, 0.5, 0.908));
  t.emplace_back(Slab(0.542, 2.63, -0.5, 0.5, 0.0));
  t.emplace_back(Slab(-0.264, 0.536, 0.501, 0.521, 0.908));
  // Side lane y [0.5, 1.45]: floor, debris field x [-0.63, 0.93] over a pit, floor.
  t.emplace_back(Slab(-1.6, -0.66, 0.5, 1.45, 0.0));
  t.emplace_back(Slab(0.96, 2.0, 0.5, 1.45, 0.0));
  // Tops sink deeper toward the corridor and the start: top centres from -0.0725 to +0.0025 m,
  // top faces spanning z -0.104 to +0.041.
  AddBlockField(t, {-0.48, -0.16, 0.46, 0.78}, {0.64, 0.865, 1.09, 1.315},
                [](int c, int r, bool pitched) { return -0.08 + 0.015 * r + 0.0075 * c + (pitched ? 0.015 : 0.0); });
  t.emplace_back(Slab(0.0, 0.30, 0.5925, 1.3625, 0.019));
  s.start = Pose(-1.5, 0.0);
  s.goal = Pose(2.2, 0.0);
  return b;
}

BenchmarkScenario Plinth() {
  BenchmarkScenario b;
  b.description =
      "plinth: 1.04 m wide, three 0.17 m steps up (0.29 m treads) to a 0.58 m long top at z = 0.51, "
      "three steps down";
  Scenario& s = b.scenario;
  s.name = "plinth";
  auto& t = s.terrain;
  constexpr double y0 = -0.52;
  constexpr double y1 = 0.52;
  t.emplace_back(Slab(-3.0, -0.87, y0, y1, 0.0));
  t.emplace_back(Slab(-0.87, -0.58, y0, y1, 0.17));
  t.emplace_back(Slab(-0.58, -0.29, y0, y1, 0.34));
  t.emplace_back(Slab(-0.29, 0.29, y0, y1, 0.51));
  t.emplace_back(Slab(0.29, 0.58, y0, y1, 0.34));
  t.emplace_back(Slab(0.58, 0.87, y0, y1, 0.17));
  t.emplace_back(Slab(0.87, 3.0, y0, y1, 0.0));
  s.start = Pose(-1.7, 0.0);
  s.goal = Pose(1.7, 0.0);
  return b;
}

BenchmarkScenario DarpaRubble() {
  BenchmarkScenario b;
  b.description =
      "DARPA rubble: 4 x 4 cinder blocks tilted 15 deg (tops z 0.16-0.24) in two pairs of columns around a "
      "flat top at z = 0.342, side stairs at z 0.10 and 0.20, floors at both ends";
  Scenario& s = b.scenario;
  s.name = "darpa_rubble";
  auto& t = s.terrain;
  constexpr double kFloorY0 = -0.85;
  constexpr double kFloorY1 = 0.76;
  t.emplace_back(Slab(-3.0, -0.625, kFloorY0, kFloorY1, 0.0));
  t.emplace_back(Slab(1.075, 3.5, kFloorY0, kFloorY1, 0.0));
  // Side stairs beside the block field: step 0.10, strip 0.20, step 0.10.
  for (const auto& [sy0, sy1] : {std::pair{-0.83, -0.53}, std::pair{0.44, 0.74}}) {
    t.emplace_back(Slab(-0.625, -0.325, sy0, sy1, 0.10));
    t.emplace_back(Slab(-0.325, 0.775, sy0, sy1, 0.20));
    t.emplace_back(Slab(0.775, 1.075, sy0, sy1, 0.10));
  }
  // Pitched blocks sit 1.5 cm higher than rolled ones: their high edges then clear the rolled
  // neighbours they overhang.
  AddBlockField(t, {-0.405, -0.085, 0.535, 0.855}, {-0.3825, -0.1575, 0.0675, 0.2925},
                [](int, int, bool pitched) { return pitched ? 0.205 : 0.19; });
  t.emplace_back(Slab(0.075, 0.375, -0.43, 0.34, 0.342));
  s.start = Pose(-1.2, 0.0);
  s.goal = Pose(1.7, 0.0);
  return b;
}

/// The scenario exactly as its file will hold it (numbers rounded by the canonical format).
BenchmarkScenario AsWritten(BenchmarkScenario b) {
  b.scenario = ParseScenario(ScenarioToYaml(b.scenario), "");
  return b;
}

}  // namespace

std::vector<BenchmarkScenario> MakeBenchmarkScenarios() {
  return {AsWritten(FlatGround()), AsWritten(SlalomDebris()), AsWritten(Plinth()), AsWritten(DarpaRubble())};
}

std::string BenchmarkScenarioText(const BenchmarkScenario& benchmark) {
  const std::string text =
      ScenarioToYaml(benchmark.scenario, {"generated by generate_scenarios; do not edit", benchmark.description});
  const Scenario loaded = ParseScenario(text, benchmark.scenario.name + ".yaml");
  const std::vector<std::size_t> covered = FindCoveredUpwardTriangles(loaded.terrain_mesh);
  RBCP_CHECK(covered.empty(), benchmark.scenario.name + ": triangle " +
                                  (covered.empty() ? std::string() : std::to_string(covered.front())) +
                                  " is an upward face covered by another box");
  return text;
}

}  // namespace rbcp
