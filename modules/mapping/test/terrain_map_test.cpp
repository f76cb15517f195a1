#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

#include "box_scene.h"
#include "rbcp/core/error.h"
#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping {
namespace {

using test_scene::Box;
using test_scene::Camera;
using test_scene::Capture;
using test_scene::Scene;

constexpr double kNoise = 0.01;  // 1 cm range noise

/// The mean height of the known cells whose centres lie in [x0, x1] x [y0, y1], and their count.
std::pair<double, int> MeanHeight(const ElevationMap& map, double x0, double x1, double y0, double y1) {
  double sum = 0.0;
  int count = 0;
  for (int iy = 0; iy < map.num_y(); ++iy) {
    for (int ix = 0; ix < map.num_x(); ++ix) {
      const Eigen::Vector2d c = map.CellCentre(ix, iy);
      const auto cell = map.At(ix, iy);
      if (!cell || c.x() < x0 || c.x() > x1 || c.y() < y0 || c.y() > y1) continue;
      sum += cell->height;
      ++count;
    }
  }
  return {count ? sum / count : std::nan(""), count};
}

TEST(TerrainMap, ABoxOnFlatGroundShowsItsTopAndTheGroundAround) {
  const Scene scene{{Box{{0.9, -0.15, 0.0}, {1.2, 0.15, 0.15}}}};
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  std::mt19937 rng(7);
  Camera cam;  // at 0.5 m, looking along +x, 0.5 rad down
  IntegrateReport total;
  for (int i = 0; i < 5; ++i) {
    const IntegrateReport r = map.Integrate(Capture(scene, cam, kNoise, rng));
    total.points_fused += r.points_fused;
    total.points_invalid += r.points_invalid;
  }
  EXPECT_GT(total.points_fused, 10000u);
  EXPECT_EQ(total.points_invalid, 0u);
  // The box's top, a cell in from its edges; the ground in front of it.
  const auto [top, top_cells] = MeanHeight(map.elevation(), 0.95, 1.15, -0.1, 0.1);
  EXPECT_GT(top_cells, 10);
  EXPECT_NEAR(top, 0.15, 0.01);
  const auto [ground, ground_cells] = MeanHeight(map.elevation(), 0.5, 0.8, -0.3, 0.3);
  EXPECT_GT(ground_cells, 50);
  EXPECT_NEAR(ground, 0.0, 0.01);
  const HeightError e = MeasureHeightError(map.elevation(), scene.Truth());
  EXPECT_EQ(e.cells, map.elevation().KnownCells());
  EXPECT_EQ(e.cells_no_truth, 0u);
  EXPECT_LE(e.rms_m, 0.02);
}

TEST(TerrainMap, HeightErrorTakesEitherSideOfAnEdgeThroughACellAndAFaceHeightInFull) {
  // A box 0.2 m high whose side x = 0.55 runs through the cells centred at x = 0.54 (4 cm cells
  // on multiples of 0.04).
  const Scene scene{{Box{{0.55, -1.0, 0.0}, {1.5, 1.0, 0.2}}}};
  ElevationMap map(MapperConfig().elevation);
  map.Recenter({0, 0});
  const auto set = [&](double x, double z) {
    for (double y = -0.3; y <= 0.3; y += 0.04) map.Fuse({x, y + 0.02, z}, 1e-6);
  };
  set(0.30, 0.0);   // on the ground
  set(0.70, 0.2);   // on the box's top
  set(0.54, 0.0);   // the edge's cells at the ground's height: right
  EXPECT_LE(MeasureHeightError(map, scene.Truth()).max_m, 1e-6);
  set(0.54, 0.2);   // ... or at the top's: right too
  EXPECT_LE(MeasureHeightError(map, scene.Truth()).max_m, 1e-6);
  set(0.54, 0.1);   // a height of the box's side, which no point of these cells has on top
  const HeightError e = MeasureHeightError(map, scene.Truth());
  EXPECT_NEAR(e.max_m, 0.1, 1e-6);
  EXPECT_EQ(e.cells, map.KnownCells());
}

TEST(TerrainMap, UnseenTerrainStaysUnknownAndOutOfTheMesh) {
  // A wall 0.4 m high hides the ground behind it from a camera at 0.5 m.
  const Scene scene{{Box{{1.0, -1.0, 0.0}, {1.1, 1.0, 0.4}}}};
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  std::mt19937 rng(3);
  map.Integrate(Capture(scene, Camera(), kNoise, rng));
  // Behind the camera, and in the wall's shadow.
  EXPECT_FALSE(map.elevation().At(Eigen::Vector2d(-1.0, 0.0)));
  EXPECT_FALSE(map.elevation().At(Eigen::Vector2d(1.4, 0.0)));
  EXPECT_TRUE(map.elevation().At(Eigen::Vector2d(0.7, 0.0)));
  const TriangleMesh mesh = map.ToMesh();
  ASSERT_FALSE(mesh.Empty());
  for (const Eigen::Vector3d& v : mesh.vertices) {
    EXPECT_TRUE(v.x() > 0.0) << v.transpose();
    EXPECT_FALSE(v.x() > 1.25 && v.x() < 1.6 && std::abs(v.y()) < 0.5) << v.transpose();
  }
}

TEST(TerrainMap, AWallWhoseTopWasNeverSeenIsMeshedHighAboveItsFace) {
  // A wall 2 cm thick and 1.4 m high across the camera's view: the camera, at 0.5 m and pitched
  // down, sees its face up to about 0.37 m and never its top.
  const Scene scene{{Box{{1.0, -1.0, 0.0}, {1.02, 1.0, 1.4}}}};
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  std::mt19937 rng(5);
  for (int i = 0; i < 3; ++i) map.Integrate(Capture(scene, Camera(), kNoise, rng));
  double face_top = 0.0;  // the highest known cell at the wall
  for (int iy = 0; iy < map.elevation().num_y(); ++iy) {
    for (int ix = 0; ix < map.elevation().num_x(); ++ix) {
      const Eigen::Vector2d c = map.elevation().CellCentre(ix, iy);
      const auto cell = map.elevation().At(ix, iy);
      if (cell && std::abs(c.x() - 1.01) < 0.03) face_top = std::max(face_top, cell->height);
    }
  }
  EXPECT_LT(face_top, 0.5) << "the elevation map keeps what was measured: the face";
  int at_wall = 0;
  const TriangleMesh mesh = map.ToMesh();
  for (const Eigen::Vector3d& v : mesh.vertices) {
    if (std::abs(v.x() - 1.01) < 0.02 && std::abs(v.y()) < 0.3) {
      ++at_wall;
      EXPECT_GT(v.z(), 1.2) << "the mesh stands the wall a metre above its face: " << v.transpose();
    }
    if (v.x() < 0.9) EXPECT_NEAR(v.z(), 0.0, 0.02) << "the ground before it is untouched: " << v.transpose();
  }
  EXPECT_GT(at_wall, 5);
}

TEST(TerrainMap, ABlockWhoseTopWasSeenIsMeshedNoHigherThanItsTop) {
  const Scene scene{{Box{{0.9, -0.15, 0.0}, {1.2, 0.15, 0.3}}}};
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  std::mt19937 rng(5);
  for (int i = 0; i < 3; ++i) map.Integrate(Capture(scene, Camera(), kNoise, rng));
  const TriangleMesh mesh = map.ToMesh();
  ASSERT_FALSE(mesh.Empty());
  double highest = 0.0;
  for (const Eigen::Vector3d& v : mesh.vertices) highest = std::max(highest, v.z());
  EXPECT_GT(highest, 0.28);
  EXPECT_LT(highest, 0.36) << "the top was seen: it is no obstacle of unknown height";
}

TEST(TerrainMap, AVoxelAcrossABlocksEdgeDoesNotRaiseTheBlocksTop) {
  // A rubble block 0.24 m high whose near side lies inside an octree voxel column (5 cm): that
  // column holds the floor at the block's foot and the top's returns, some of which the noise
  // puts into the voxel above 0.25 m. A camera walking up to it sees over its top.
  const double top = 0.24;
  const Scene scene{{Box{{0.92, -0.15, 0.0}, {1.22, 0.15, top}}}};
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  std::mt19937 rng(5);
  for (int i = 0; i < 8; ++i) {
    Camera cam;
    cam.origin.x() = 0.1 * i;
    cam.cols = 160;
    cam.rows = 120;
    map.Integrate(Capture(scene, cam, kNoise, rng));
  }
  int on_block = 0;
  for (const Eigen::Vector3d& v : map.ToMesh().vertices) {
    if (v.x() < 0.9 || v.x() > 1.25 || std::abs(v.y()) > 0.17) continue;
    ++on_block;
    EXPECT_LT(v.z(), top + 0.03) << "no higher than the top the cells measured: " << v.transpose();
  }
  EXPECT_GT(on_block, 20);
}

/// The RMS height error of the known cells whose centres lie within `band` of a box's side (xy),
/// and of the others.
std::pair<double, double> EdgeAndOtherRms(const ElevationMap& map, const Scene& scene, double band) {
  double sum[2] = {0, 0};
  int count[2] = {0, 0};
  for (int iy = 0; iy < map.num_y(); ++iy) {
    for (int ix = 0; ix < map.num_x(); ++ix) {
      const auto cell = map.At(ix, iy);
      if (!cell) continue;
      const Eigen::Vector2d c = map.CellCentre(ix, iy);
      double top = 0.0;
      bool near_side = false;
      for (const Box& b : scene.boxes) {
        const bool in = c.x() > b.lo.x() && c.x() < b.hi.x() && c.y() > b.lo.y() && c.y() < b.hi.y();
        if (in) top = std::max(top, b.hi.z());
        const bool in_outer = c.x() > b.lo.x() - band && c.x() < b.hi.x() + band && c.y() > b.lo.y() - band &&
                              c.y() < b.hi.y() + band;
        const bool in_inner = c.x() > b.lo.x() + band && c.x() < b.hi.x() - band && c.y() > b.lo.y() + band &&
                              c.y() < b.hi.y() - band;
        near_side = near_side || (in_outer && !in_inner);
      }
      const double e = cell->height - top;
      sum[near_side] += e * e;
      ++count[near_side];
    }
  }
  return {std::sqrt(sum[1] / std::max(count[1], 1)), std::sqrt(sum[0] / std::max(count[0], 1))};
}

/// The map after 10 clouds from each of six places around the field (towards it, and from both
/// sides), with 1 cm range noise.
TerrainMap MapOf(const Scene& scene, std::mt19937& rng) {
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  const std::vector<Eigen::Vector3d> poses = {{-0.6, 0.0, 0.0}, {0.0, -0.6, 0.5}, {0.0, 0.6, -0.5}, {0.3, 0.0, 0.0},
                                              {1.4, -1.6, 1.57}, {1.4, 1.6, -1.57}};
  for (const Eigen::Vector3d& pose : poses) {
    Camera cam;
    cam.origin = {pose.x(), pose.y(), 0.5};
    cam.yaw_rad = pose.z();
    for (int i = 0; i < 10; ++i) map.Integrate(Capture(scene, cam, kNoise, rng));
  }
  return map;
}

/// The map's height error against the scene, with the RMS near the blocks' sides and elsewhere;
/// printed, as the figures the tests bound.
struct RubbleError {
  HeightError all;
  double near_sides_rms = 0.0;
  double elsewhere_rms = 0.0;
};
RubbleError MeasureRubble(const char* name, const TerrainMap& map, const Scene& scene) {
  RubbleError r;
  r.all = MeasureHeightError(map.elevation(), scene.Truth());
  std::tie(r.near_sides_rms, r.elsewhere_rms) = EdgeAndOtherRms(map.elevation(), scene, 0.02);
  std::printf("%s: %zu cells, rms %.4f m, p95 %.4f m, max %.4f m; within 2 cm of a side %.4f m, elsewhere %.4f m\n",
              name, r.all.cells, r.all.rms_m, r.all.p95_m, r.all.max_m, r.near_sides_rms, r.elsewhere_rms);
  return r;
}

// The cells whose centre lies within the range noise of a block's side can read either surface
// (the points of a block's top scatter about 1 cm sideways past its edge): they make most of the
// error, so the error near the sides and away from them are checked apart.
TEST(TerrainMap, HeightErrorOnRubbleSeenFromSeveralPoses) {
  std::mt19937 rng(11);
  const Scene scene = test_scene::Rubble(10, 0.6, 2.6, -1.0, 1.0, rng);
  const RubbleError r = MeasureRubble("rubble (10 blocks)", MapOf(scene, rng), scene);
  const HeightError& e = r.all;
  EXPECT_GT(e.cells, 3000u);
  EXPECT_EQ(e.cells_no_truth, 0u);
  EXPECT_LE(e.rms_m, 0.02);
  EXPECT_LE(e.p95_m, 0.015);
  EXPECT_LE(r.elsewhere_rms, 0.01);
}

TEST(TerrainMap, HeightErrorOnDenseStackedRubble) {
  std::mt19937 rng(11);
  const Scene scene = test_scene::Rubble(14, 0.6, 2.2, -0.9, 0.9, rng);
  const RubbleError r = MeasureRubble("dense rubble (14 blocks)", MapOf(scene, rng), scene);
  const HeightError& e = r.all;
  // A quarter of its cells lie within 2 cm of a side (stacked blocks up to 0.37 m).
  EXPECT_LE(e.rms_m, 0.02);
  EXPECT_LE(e.p95_m, 0.015);
  EXPECT_LE(r.elsewhere_rms, 0.02);
}

TEST(TerrainMap, ARemovedBoxDisappears) {
  const Box box{{0.9, -0.15, 0.0}, {1.2, 0.15, 0.15}};
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  std::mt19937 rng(5);
  for (int i = 0; i < 10; ++i) map.Integrate(Capture(Scene{{box}}, Camera(), kNoise, rng));
  ASSERT_NEAR(MeanHeight(map.elevation(), 0.95, 1.15, -0.1, 0.1).first, 0.15, 0.01);
  std::size_t cleared = 0;
  for (int i = 0; i < 30; ++i) cleared += map.Integrate(Capture(Scene{}, Camera(), kNoise, rng)).cells_cleared;
  EXPECT_GT(cleared, 20u);
  const auto [height, cells] = MeanHeight(map.elevation(), 0.9, 1.2, -0.15, 0.15);
  EXPECT_GT(cells, 40);
  EXPECT_NEAR(height, 0.0, 0.01);
  const HeightError e = MeasureHeightError(map.elevation(), Scene{}.Truth());
  EXPECT_LE(e.max_m, 0.05);
}

TEST(TerrainMap, GroundSeenAgainAndAgainIsNotCleared) {
  // Flat ground only, seen at grazing angles far out: rays pass just over the ground cells.
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  std::mt19937 rng(9);
  Camera cam;
  cam.pitch_rad = 0.25;
  std::size_t cleared = 0;
  for (int i = 0; i < 40; ++i) cleared += map.Integrate(Capture(Scene{}, cam, kNoise, rng)).cells_cleared;
  const std::size_t known = map.elevation().KnownCells();
  EXPECT_GT(known, 2000u);
  EXPECT_LE(cleared, known / 100) << cleared << " of " << known;
}

TEST(TerrainMap, HostileCloudsAreCountedOrRejected) {
  MapperConfig config;
  config.max_points_per_cloud = 100;
  TerrainMap map(config);
  map.Recenter({0, 0});
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  WorldCloud cloud;
  cloud.origin = {0, 0, 0.5};
  cloud.range_noise_std = 0.01;
  cloud.points = {{1, 0, 0}, {nan, 0, 0}, {1, inf, 0}, {1, 0.1, -inf}, {50, 0, 0}, {1.5, 0.2, 0.0}};
  const IntegrateReport r = map.Integrate(cloud);
  EXPECT_EQ(r.points_invalid, 3u);
  EXPECT_EQ(r.points_outside, 1u);
  EXPECT_EQ(r.points_fused, 2u);
  EXPECT_EQ(map.elevation().KnownCells(), 2u);

  // A bad origin or too many points: InputError, and the map is as it was.
  const std::size_t nodes = map.OccupancyNodes();
  WorldCloud bad = cloud;
  bad.origin.x() = nan;
  bad.points = {{0.5, 0.5, 0.0}};
  EXPECT_THROW(map.Integrate(bad), InputError);
  WorldCloud big = cloud;
  big.points.assign(101, Eigen::Vector3d(0.5, 0.5, 0.0));
  EXPECT_THROW(map.Integrate(big), InputError);
  EXPECT_EQ(map.elevation().KnownCells(), 2u);
  EXPECT_FALSE(map.elevation().At(Eigen::Vector2d(0.5, 0.5)));
  EXPECT_EQ(map.OccupancyNodes(), nodes);

  // No points: nothing happens.
  WorldCloud empty;
  empty.origin = {0, 0, 0.5};
  const IntegrateReport e = map.Integrate(empty);
  EXPECT_EQ(e.points_fused + e.points_outside + e.points_invalid, 0u);
  // Beyond max_range_m but inside the window: outside too.
  WorldCloud far = empty;
  far.points = {{3.9, 3.9, 0.0}};
  EXPECT_EQ(map.Integrate(far).points_outside, 1u);
}

TEST(TerrainMap, AStanceFootMarksTheCellsUnderItsSole) {
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  map.IntegrateContact({0.3, 0.1, 0.05}, 1e-6);
  const ElevationMap& e = map.elevation();
  EXPECT_GE(e.KnownCells(), 1u);
  EXPECT_LE(e.KnownCells(), 9u);
  EXPECT_NEAR(e.At(Eigen::Vector2d(0.3, 0.1))->height, 0.05, 1e-6);
  // A foot standing lower than a cell's height moves it down (no gate).
  map.IntegrateContact({0.3, 0.1, 0.0}, 1e-6);
  EXPECT_NEAR(e.At(Eigen::Vector2d(0.3, 0.1))->height, 0.0, 1e-6);
  EXPECT_FALSE(e.At(Eigen::Vector2d(0.4, 0.1)));
  EXPECT_THROW(map.IntegrateContact({std::nan(""), 0, 0}, 1e-6), InputError);
}

TEST(TerrainMap, MemoryStaysBoundedOnALongWalk) {
  TerrainMap map{MapperConfig()};
  std::mt19937 rng(13);
  // Boxes every metre along 50 m of walk.
  Scene scene;
  scene.ground_half_extent_m = 60.0;
  for (int i = 1; i < 56; ++i) scene.boxes.push_back({{i - 0.2, -0.3, 0.0}, {i + 0.2, 0.3, 0.1 + 0.02 * (i % 5)}});
  std::size_t peak_bytes = 0, peak_nodes = 0;
  for (double x = 0.0; x <= 50.0; x += 0.25) {
    map.Recenter({x, 0.0});
    Camera cam;
    cam.origin = {x, 0.0, 0.5};
    map.Integrate(Capture(scene, cam, kNoise, rng));
    peak_bytes = std::max(peak_bytes, map.MemoryBytes());
    peak_nodes = std::max(peak_nodes, map.OccupancyNodes());
  }
  std::printf("50 m walk: peak %.1f MB, %zu octree nodes; at the end %.1f MB, %zu nodes\n", peak_bytes / 1e6,
              peak_nodes, map.MemoryBytes() / 1e6, map.OccupancyNodes());
  EXPECT_LT(peak_bytes, 50u * 1000u * 1000u);
  EXPECT_LT(peak_nodes, 1000000u);
  // Nothing of the start is left: the octree and the map hold only the window.
  EXPECT_FALSE(map.elevation().At(Eigen::Vector2d(1.0, 0.0)));
  const TriangleMesh mesh = map.ToMesh();
  for (const Eigen::Vector3d& v : mesh.vertices) EXPECT_GT(v.x(), 45.0);
}

}  // namespace
}  // namespace rbcp::mapping

namespace rbcp::mapping {
namespace {

TEST(TerrainMap, AMapStartsWithTheGroundUnderTheStandingRobot) {
  TerrainMap map{MapperConfig()};
  map.Recenter({0, 0});
  // A cell seen before stays as seen.
  map.IntegrateContact({0.0, 0.0, 0.3}, 1e-4);
  const std::vector<Eigen::Vector3d> feet = {{0.35, 0.25, 0.1}, {0.35, -0.25, 0.1}, {-0.35, 0.25, 0.1}, {-0.35, -0.25, 0.1}};
  map.InitializeFootprint(feet, 0.1, 4e-4);
  const ElevationMap& grid = map.elevation();
  ASSERT_TRUE(grid.At(Eigen::Vector2d(0.0, 0.0)).has_value());
  EXPECT_NEAR(grid.At(Eigen::Vector2d(0.0, 0.0))->height, 0.3, 1e-6) << "known before: kept";
  for (const Eigen::Vector2d xy : {Eigen::Vector2d(0.2, 0.1), Eigen::Vector2d(-0.3, -0.2), Eigen::Vector2d(0.42, 0.3)}) {
    const auto cell = grid.At(xy);
    ASSERT_TRUE(cell.has_value()) << xy.transpose();
    EXPECT_NEAR(cell->height, 0.1, 1e-6);
    EXPECT_NEAR(cell->variance, 4e-4, 1e-9);
  }
  EXPECT_FALSE(grid.At(Eigen::Vector2d(0.55, 0.0)).has_value()) << "beyond the margin";
  EXPECT_FALSE(grid.At(Eigen::Vector2d(0.0, 0.45)).has_value());
  EXPECT_THROW(map.InitializeFootprint({feet[0], feet[1]}, 0.1, 4e-4), InputError);
}

}  // namespace
}  // namespace rbcp::mapping
