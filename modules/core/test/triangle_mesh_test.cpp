#include "rbcp/core/triangle_mesh.h"

#include <gtest/gtest.h>

#include <limits>

namespace rbcp {
namespace {

TEST(TriangleMesh, BoxHasOutwardNormalsAndTheRightArea) {
  const TriangleMesh box = MakeBoxMesh({2.0, 3.0, 4.0});
  ASSERT_EQ(box.NumTriangles(), 12u);
  double area = 0.0;
  for (std::size_t t = 0; t < box.NumTriangles(); ++t) {
    area += box.Area(t);
    Eigen::Vector3d centroid = (box.Corner(t, 0) + box.Corner(t, 1) + box.Corner(t, 2)) / 3.0;
    EXPECT_GT(box.AreaNormal(t).dot(centroid), 0.0) << "triangle " << t << " points inward";
  }
  EXPECT_NEAR(area, 2.0 * (2 * 3 + 2 * 4 + 3 * 4), 1e-12);
  EXPECT_EQ(ValidateMesh(box), "");
}

TEST(TriangleMesh, AppendingManyMeshesReallocatesRarely) {
  // Reserving exactly the new size on every append reallocates (and copies) every time: time
  // quadratic in the number of meshes appended.
  const TriangleMesh box = MakeBoxMesh({0.1, 0.1, 0.1});
  TriangleMesh all;
  int reallocations = 0;
  const std::array<int, 3>* data = all.triangles.data();
  for (int i = 0; i < 10000; ++i) {
    all.Append(box);
    if (all.triangles.data() != data) ++reallocations;
    data = all.triangles.data();
  }
  EXPECT_EQ(all.NumTriangles(), 10000u * box.NumTriangles());
  EXPECT_LT(reallocations, 40);
}

TEST(TriangleMesh, AppendOffsetsIndicesAndTransformMoves) {
  TriangleMesh a = MakeBoxMesh({1, 1, 1});
  TriangleMesh b = MakeBoxMesh({1, 1, 1});
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(5, 0, 0);
  b.Transform(T, 2.0);
  a.Append(b);
  EXPECT_EQ(a.NumTriangles(), 24u);
  EXPECT_EQ(a.vertices.size(), 16u);
  EXPECT_EQ(a.triangles[12][0], 8);
  EXPECT_NEAR(a.vertices[15].x(), 6.0, 1e-12);
  EXPECT_EQ(ValidateMesh(a), "");
}

TEST(TriangleMesh, ValidationNamesTheProblem) {
  TriangleMesh m = MakeBoxMesh({1, 1, 1});
  m.vertices[3].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ValidateMesh(m), "vertex 3 is not finite");
  m = MakeBoxMesh({1, 1, 1});
  m.triangles[2] = {0, 0, 1};
  EXPECT_NE(ValidateMesh(m).find("triangle 2 is degenerate"), std::string::npos);
  m.triangles[2] = {0, 1, 99};
  EXPECT_NE(ValidateMesh(m).find("refers to vertex 99"), std::string::npos);
  EXPECT_EQ(ValidateMesh(TriangleMesh{}), "mesh has no triangles");
}

}  // namespace
}  // namespace rbcp
