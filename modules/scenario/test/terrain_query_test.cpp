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
