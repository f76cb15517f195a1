#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping {
namespace {

ElevationMapConfig SmallWindow() {
  ElevationMapConfig c;
  c.resolution_m = 0.1;
  c.window_m = 2.0;  // 20 x 20 cells
  c.recenter_distance_m = 0.3;
  return c;
}

TEST(ElevationMap, TheWindowIsPlacedOnWholeCellsAroundThePosition) {
  ElevationMap map(SmallWindow());
  EXPECT_EQ(map.num_x(), 20);
  EXPECT_FALSE(map.Index({0, 0}));  // not placed yet
  map.Recenter({0.33, -0.27});
  EXPECT_TRUE(map.placed());
  // The cell holding the position is the middle one; the origin is a multiple of the resolution.
  EXPECT_EQ(*map.Index({0.33, -0.27}), std::make_pair(10, 10));
  EXPECT_NEAR(map.origin().x(), -0.7, 1e-12);
  EXPECT_NEAR(map.origin().y(), -1.3, 1e-12);
  EXPECT_TRUE((map.CellCentre(10, 10) - Eigen::Vector2d(0.35, -0.25)).norm() < 1e-12);
  EXPECT_FALSE(map.Index({1.4, 0}));
  EXPECT_FALSE(map.At(Eigen::Vector2d(0.3, -0.3)));
  EXPECT_EQ(map.KnownCells(), 0u);
}

TEST(ElevationMap, FusesByTheKalmanUpdateAndFloorsTheVariance) {
  ElevationMap map(SmallWindow());
  map.Recenter({0, 0});
  EXPECT_TRUE(map.Fuse({0.05, 0.05, 0.10}, 1e-4));
  EXPECT_TRUE(map.Fuse({0.01, 0.09, 0.12}, 3e-4));
  const auto cell = map.At(Eigen::Vector2d(0.05, 0.05));
  ASSERT_TRUE(cell);
  EXPECT_NEAR(cell->height, (3e-4 * 0.10 + 1e-4 * 0.12) / 4e-4, 1e-6);
  EXPECT_NEAR(cell->variance, 1e-4 * 3e-4 / 4e-4, 1e-9);
  EXPECT_EQ(map.KnownCells(), 1u);
  for (int i = 0; i < 1000; ++i) map.Fuse({0.05, 0.05, 0.105}, 1e-5);
  EXPECT_NEAR(map.At(Eigen::Vector2d(0.05, 0.05))->variance, 1e-6, 1e-12);  // min_variance_m2
}

TEST(ElevationMap, AMuchHigherPointReplacesAndAMuchLowerOneIsGated) {
  ElevationMap map(SmallWindow());
  map.Recenter({0, 0});
  map.FuseCell(10, 10, 0.0, 1e-4, 0.03);
  // 3 sigma of sqrt(2e-4) is 4.2 cm.
  EXPECT_EQ(map.FuseCell(10, 10, -0.05, 1e-4, 0.04), ElevationMap::FuseOutcome::kGated);  // past an edge
  EXPECT_NEAR(map.At(10, 10)->height, 0.0, 1e-7);
  EXPECT_EQ(map.FuseCell(10, 10, 0.2, 1e-4, 0.02), ElevationMap::FuseOutcome::kReplaced);
  EXPECT_NEAR(map.At(10, 10)->height, 0.2, 1e-7);
  EXPECT_NEAR(map.At(10, 10)->variance, 1e-4, 1e-10);
  EXPECT_FALSE(map.Fuse({0.08, 0.02, 0.1}, 1e-4));  // lower, and farther from the centre: gated
  EXPECT_FALSE(map.Fuse({5.0, 0.05, 0.1}, 1e-4));   // outside
  EXPECT_NEAR(map.At(10, 10)->height, 0.2, 1e-7);
  // Where two surfaces share a cell, the one measured nearer the centre wins.
  EXPECT_EQ(map.FuseCell(10, 10, 0.05, 1e-4, 0.01), ElevationMap::FuseOutcome::kReplaced);
  EXPECT_EQ(map.FuseCell(10, 10, 0.2, 1e-4, 0.04), ElevationMap::FuseOutcome::kGated);
  EXPECT_NEAR(map.At(10, 10)->height, 0.05, 1e-7);
  // Something new put down: higher measurements turned away grow the support until one wins.
  int turned_away = 0;
  while (map.FuseCell(10, 10, 0.3, 1e-4, 0.06) == ElevationMap::FuseOutcome::kGated) ++turned_away;
  EXPECT_GE(turned_away, 1);
  EXPECT_LE(turned_away, 10);
  EXPECT_NEAR(map.At(10, 10)->height, 0.3, 1e-7);
  // Without the gate (a foot's contact) a lower height replaces wherever it is.
  EXPECT_EQ(map.FuseCell(10, 10, 0.1, 1e-4, 0.09, /*gate=*/false), ElevationMap::FuseOutcome::kReplaced);
  EXPECT_NEAR(map.At(10, 10)->height, 0.1, 1e-7);
}

TEST(ElevationMap, RecenterKeepsCellsInTheWorldAndForgetsThoseThatLeave) {
  ElevationMap map(SmallWindow());
  map.Recenter({0, 0});
  map.Fuse({0.55, 0.25, 0.3}, 1e-4);   // stays in the window
  map.Fuse({-0.95, 0.05, 0.4}, 1e-4);  // leaves it
  ASSERT_EQ(map.KnownCells(), 2u);
  map.Recenter({0.2, 0.1});  // within recenter_distance_m: nothing moves
  EXPECT_NEAR(map.origin().x(), -1.0, 1e-12);
  map.Recenter({0.62, 0.0});
  EXPECT_NEAR(map.origin().x(), -0.4, 1e-12);
  EXPECT_EQ(map.KnownCells(), 1u);
  EXPECT_NEAR(map.At(Eigen::Vector2d(0.55, 0.25))->height, 0.3, 1e-7);
  EXPECT_FALSE(map.At(Eigen::Vector2d(-0.95, 0.05)));
  // The cells entering the window are unknown.
  for (int iy = 0; iy < map.num_y(); ++iy) EXPECT_FALSE(map.At(map.num_x() - 1, iy));
  // A jump farther than the window forgets everything.
  map.Recenter({100.0, -50.0});
  EXPECT_EQ(map.KnownCells(), 0u);
  EXPECT_TRUE(map.Index({100.0, -50.0}));
}

TEST(ElevationMap, AFlatKnownSquareMeshesFacingUp) {
  ElevationMap map(SmallWindow());
  map.Recenter({0, 0});
  for (int iy = 3; iy < 8; ++iy) {
    for (int ix = 4; ix < 10; ++ix) {
      const Eigen::Vector2d c = map.CellCentre(ix, iy);
      map.Fuse({c.x(), c.y(), 0.2}, 1e-4);
    }
  }
  map.Fuse({0.95, 0.95, 0.2}, 1e-4);  // an isolated cell: no triangle, so no vertex
  const TriangleMesh mesh = map.ToMesh();
  EXPECT_EQ(mesh.vertices.size(), 30u);
  EXPECT_EQ(mesh.triangles.size(), 2u * 4u * 5u);
  for (std::size_t t = 0; t < mesh.NumTriangles(); ++t) {
    const Eigen::Vector3d n = mesh.AreaNormal(t).normalized();
    EXPECT_NEAR(n.z(), 1.0, 1e-9);
    EXPECT_NEAR(mesh.Area(t), 0.5 * 0.1 * 0.1, 1e-9);
  }
  for (const Eigen::Vector3d& v : mesh.vertices) EXPECT_NEAR(v.z(), 0.2, 1e-6);
  EXPECT_EQ(ValidateMesh(mesh), "");
}

TEST(ElevationMap, ATiltedBlockTopMeshesAsOnePlane) {
  // A block top tilted 15 degrees (it rises about a centimetre per 4 cm cell), measured with
  // 3 mm of noise per cell: the mesh puts every cell on one plane, as it does a level top, tilted
  // as the top is within a degree.
  ElevationMapConfig config;
  config.resolution_m = 0.04;
  config.window_m = 2.0;
  ElevationMap map(config);
  map.Recenter({0, 0});
  const double tilt = 15.0 * M_PI / 180.0;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.003);
  std::vector<std::pair<int, int>> cells;
  for (int iy = 20; iy < 32; ++iy) {
    for (int ix = 20; ix < 32; ++ix) {
      const Eigen::Vector2d c = map.CellCentre(ix, iy);
      map.Fuse({c.x(), c.y(), 0.2 + std::tan(tilt) * c.x() + noise(rng)}, 1e-4);
      cells.emplace_back(ix, iy);
    }
  }
  const std::vector<float> heights = map.MeshHeights();
  // The least-squares plane of the mesh's heights, and how far they lie from it.
  Eigen::MatrixXd a(cells.size(), 3);
  Eigen::VectorXd z(cells.size());
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const auto [ix, iy] = cells[k];
    const Eigen::Vector2d c = map.CellCentre(ix, iy);
    a.row(static_cast<Eigen::Index>(k)) << c.x(), c.y(), 1.0;
    z(static_cast<Eigen::Index>(k)) = heights[static_cast<std::size_t>(iy * map.num_x() + ix)];
  }
  const Eigen::Vector3d plane = a.colPivHouseholderQr().solve(z);
  EXPECT_LT((a * plane - z).cwiseAbs().maxCoeff(), 1e-4) << "one plane, not 3 mm of noise about one";
  EXPECT_NEAR(std::atan(plane.x()), tilt, 1.0 * M_PI / 180.0);
  EXPECT_NEAR(plane.y(), 0.0, 0.01);
}

TEST(ElevationMap, ThreeKnownCellsOfABlockMakeOneTriangle) {
  for (int missing = 0; missing < 4; ++missing) {
    ElevationMap map(SmallWindow());
    map.Recenter({0, 0});
    const int corner[4][2] = {{5, 5}, {6, 5}, {6, 6}, {5, 6}};
    for (int k = 0; k < 4; ++k) {
      if (k == missing) continue;
      const Eigen::Vector2d c = map.CellCentre(corner[k][0], corner[k][1]);
      map.Fuse({c.x(), c.y(), 0.1 * k}, 1e-4);
    }
    const TriangleMesh mesh = map.ToMesh();
    ASSERT_EQ(mesh.triangles.size(), 1u) << missing;
    EXPECT_EQ(mesh.vertices.size(), 3u);
    EXPECT_GT(mesh.AreaNormal(0).z(), 0.0) << missing;
  }
}

TEST(ElevationMap, PathCoverageCountsThePointsWhoseCellsAreAllKnown) {
  ElevationMap map(SmallWindow());
  map.Recenter({0, 0});
  EXPECT_EQ(PathCoverage(map, {}, 0.1), 0.0);
  for (int iy = 0; iy < map.num_y(); ++iy) {
    for (int ix = 0; ix < 10; ++ix) {  // x < 0 known
      const Eigen::Vector2d c = map.CellCentre(ix, iy);
      map.Fuse({c.x(), c.y(), 0.0}, 1e-4);
    }
  }
  const std::vector<Eigen::Vector2d> path = {{-0.5, 0}, {-0.3, 0.2}, {-0.05, 0}, {0.3, 0}};
  EXPECT_DOUBLE_EQ(PathCoverage(map, path, 0.12), 0.5);   // (-0.05, 0) has unknown cells within 0.12
  EXPECT_DOUBLE_EQ(PathCoverage(map, path, 0.0), 0.75);   // only the cell under each point
  EXPECT_DOUBLE_EQ(PathCoverage(map, {{50.0, 0.0}}, 0.1), 0.0);  // outside the window
}

TEST(ElevationMap, ClearForgetsACell) {
  ElevationMap map(SmallWindow());
  map.Recenter({0, 0});
  map.Fuse({0.05, 0.05, 0.1}, 1e-4);
  map.Clear(10, 10);
  map.Clear(10, 10);
  map.Clear(-1, 3);
  EXPECT_EQ(map.KnownCells(), 0u);
  EXPECT_FALSE(map.At(10, 10));
  EXPECT_TRUE(map.ToMesh().Empty());
}

}  // namespace
}  // namespace rbcp::mapping
