#include <gtest/gtest.h>

#include <cmath>

#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

TriangleMesh Box(const Eigen::Vector3d& size, const Eigen::Vector3d& centre, const Eigen::Vector3d& rpy = {0, 0, 0}) {
  TerrainBox box;
  box.size = size;
  box.position = centre;
  box.rpy = rpy;
  return ElementMesh(box);
}

TEST(TerrainHeightAt, TopOfABoxAndNothingBesideIt) {
  const TriangleMesh m = Box({2, 1, 0.5}, {0, 0, -0.25});
  ASSERT_TRUE(TerrainHeightAt(m, {0.3, 0.2}).has_value());
  EXPECT_NEAR(*TerrainHeightAt(m, {0.3, 0.2}), 0.0, 1e-12);
  EXPECT_NEAR(*TerrainHeightAt(m, {1.0, 0.5}), 0.0, 1e-12);  // corner counts as inside
  EXPECT_FALSE(TerrainHeightAt(m, {1.01, 0.0}).has_value());
  EXPECT_FALSE(TerrainHeightAt(m, {0.0, -0.51}).has_value());
}

TEST(TerrainHeightAt, HighestOfStackedGeometry) {
  TriangleMesh m = Box({4, 4, 0.5}, {0, 0, -0.25});
  m.Append(Box({1, 1, 0.2}, {1, 1, 0.6}));  // floating slab, top at 0.7
  EXPECT_NEAR(*TerrainHeightAt(m, {1.2, 0.9}), 0.7, 1e-12);
  EXPECT_NEAR(*TerrainHeightAt(m, {-1.0, -1.0}), 0.0, 1e-12);
}

TEST(TerrainHeightAt, TiltedTop) {
  const double tilt = 15.0 * M_PI / 180.0;
  // Pitched by +15 deg: the top descends toward +x with slope tan(15 deg).
  const TriangleMesh m = Box({0.3, 0.21, 0.3}, {0, 0, 0}, {0, tilt, 0});
  const double top_centre_z = 0.15 / std::cos(tilt);  // vertical distance from centre to the top plane
  EXPECT_NEAR(*TerrainHeightAt(m, {0.0, 0.0}), top_centre_z, 1e-12);
  EXPECT_NEAR(*TerrainHeightAt(m, {0.1, 0.05}), top_centre_z - 0.1 * std::tan(tilt), 1e-12);
  EXPECT_NEAR(*TerrainHeightAt(m, {-0.1, -0.05}), top_centre_z + 0.1 * std::tan(tilt), 1e-12);
}

TEST(TerrainHeightAt, EmptyMeshHasNoHeight) { EXPECT_FALSE(TerrainHeightAt(TriangleMesh{}, {0, 0}).has_value()); }

TEST(TerrainHeightMap, AnswersAsTerrainHeightAtOverRubbleAndItsEdges) {
  // Tilted blocks on a floor, with points drawn over the whole terrain and beyond it, on the grid's
  // cell edges and on the blocks' own edges.
  TriangleMesh m = Box({3, 2, 0.5}, {0, 0, -0.25});
  for (int i = 0; i < 6; ++i) {
    m.Append(Box({0.3, 0.21, 0.3}, {-0.9 + 0.3 * i, 0.1 * (i % 3) - 0.1, 0.05}, {0.26 * ((i % 2) ? 1 : -1), 0.1 * i, 0.3 * i}));
  }
  for (double cell : {0.05, 0.1, 0.37}) {
    const TerrainHeightMap map(m, cell);
    unsigned state = 7;
    const auto uniform = [&state] {
      state = state * 1664525u + 1013904223u;
      return static_cast<double>(state >> 8) / static_cast<double>(1u << 24);
    };
    for (int k = 0; k < 4000; ++k) {
      Eigen::Vector2d xy(-1.7 + 3.4 * uniform(), -1.2 + 2.4 * uniform());
      if (k % 4 == 0) xy.x() = std::round(xy.x() / cell) * cell;  // on a cell edge
      if (k % 8 == 1) xy = m.Corner(static_cast<std::size_t>(k) % m.NumTriangles(), 0).head<2>();
      const std::optional<double> expected = TerrainHeightAt(m, xy);
      const std::optional<double> got = map.At(xy);
      ASSERT_EQ(expected.has_value(), got.has_value()) << "cell " << cell << " at " << xy.transpose();
      if (expected) {
        EXPECT_EQ(*expected, *got) << "cell " << cell << " at " << xy.transpose();
      }
    }
  }
  EXPECT_TRUE(TerrainHeightMap(TriangleMesh{}).Empty());
  EXPECT_FALSE(TerrainHeightMap(TriangleMesh{}).At({0, 0}).has_value());
}

TEST(FindCoveredUpwardTriangles, SeparateAndAbuttingBoxesAreUncovered) {
  TriangleMesh m = Box({1, 1, 0.5}, {0, 0, -0.25});  // top at 0, x [-0.5, 0.5]
  m.Append(Box({0.3, 1, 0.67}, {0.65, 0, -0.165}));  // step abutting at x = 0.5, top at 0.17
  m.Append(Box({0.5, 0.5, 0.5}, {3, 3, 0.2}));       // far away
  EXPECT_TRUE(FindCoveredUpwardTriangles(m).empty());
}

TEST(FindCoveredUpwardTriangles, BoxStandingOnAFloorCoversIt) {
  TriangleMesh m = Box({2, 2, 0.5}, {0, 0, -0.25});  // triangles 0-11, top = triangles 2 and 3
  m.Append(Box({0.4, 0.4, 0.4}, {0.5, 0.5, 0.2}));   // stands on the floor's top
  const std::vector<std::size_t> covered = FindCoveredUpwardTriangles(m);
  ASSERT_FALSE(covered.empty());
  for (std::size_t t : covered) EXPECT_TRUE(t == 2 || t == 3) << t;
}

TEST(FindCoveredUpwardTriangles, OverhangOfATiltedBlock) {
  const double tilt = 15.0 * M_PI / 180.0;
  // A 0.4 m deep block pitched so that its high edge (x = -0.093, z = 0.232) faces -x; below that
  // edge its side leans outward, reaching x = -0.155 at z = 0.
  const TriangleMesh block = Box({0.3, 0.21, 0.4}, {0, 0, 0}, {0, tilt, 0});
  // A slab with its top at z = 0 reaching to x = -0.12 lies partly under the leaning side...
  TriangleMesh under = block;
  under.Append(Box({0.3, 0.21, 0.1}, {-0.27, 0, -0.05}));
  const std::vector<std::size_t> covered = FindCoveredUpwardTriangles(under);
  ASSERT_FALSE(covered.empty());
  for (std::size_t t : covered) EXPECT_GE(t, 12u);  // only the slab's top
  // ...one ending at x = -0.17 is clear of it.
  TriangleMesh clear = block;
  clear.Append(Box({0.3, 0.21, 0.1}, {-0.32, 0, -0.05}));
  EXPECT_TRUE(FindCoveredUpwardTriangles(clear).empty());
}

}  // namespace
}  // namespace rbcp
