#include <gtest/gtest.h>

#include "rbcp/core/error.h"
#include "rbcp/scenario/scenario.h"
#include "test_paths.h"

namespace rbcp {
namespace {

using test::DataPath;

/// Signed volume by the divergence theorem: positive for a closed mesh with outward winding.
double SignedVolume(const TriangleMesh& m) {
  double v = 0.0;
  for (std::size_t t = 0; t < m.NumTriangles(); ++t)
    v += m.Corner(t, 0).dot(m.Corner(t, 1).cross(m.Corner(t, 2))) / 6.0;
  return v;
}

std::string LoadError(const std::string& path, double scale) {
  try {
    LoadMeshFile(path, scale);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LoadMeshFile, StlRampJoinsVerticesAndKeepsOutwardWinding) {
  const TriangleMesh m = LoadMeshFile(DataPath("meshes/ramp.stl"), 1.0);
  EXPECT_EQ(m.NumTriangles(), 8u);
  EXPECT_EQ(m.vertices.size(), 6u);
  EXPECT_NEAR(SignedVolume(m), 0.5 * 1.0 * 0.6 * 0.2, 1e-7);
  Eigen::Vector3d lo = m.vertices[0], hi = m.vertices[0];
  for (const auto& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3d::Zero(), 1e-7) || lo.norm() < 1e-7);
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3d(1.0, 0.6, 0.2), 1e-6));
}

TEST(LoadMeshFile, ObjInCentimetresWithScaleMatchesStl) {
  const TriangleMesh stl = LoadMeshFile(DataPath("meshes/ramp.stl"), 1.0);
  const TriangleMesh obj = LoadMeshFile(DataPath("meshes/ramp.obj"), 0.01);
  EXPECT_EQ(obj.NumTriangles(), 8u);  // three quads and two triangles
  EXPECT_EQ(obj.vertices.size(), 6u);
  EXPECT_NEAR(SignedVolume(obj), 0.06, 1e-7);
  for (const auto& v : obj.vertices) {
    double nearest = 1e9;
    for (const auto& w : stl.vertices) nearest = std::min(nearest, (v - w).norm());
    EXPECT_LT(nearest, 1e-6) << v.transpose();
  }
}

TEST(LoadMeshFile, PlyAndScale) {
  const TriangleMesh ply = LoadMeshFile(DataPath("meshes/ramp.ply"), 1.0);
  EXPECT_EQ(ply.NumTriangles(), 8u);
  EXPECT_NEAR(SignedVolume(ply), 0.06, 1e-7);
  const TriangleMesh doubled = LoadMeshFile(DataPath("meshes/ramp.ply"), 2.0);
  EXPECT_NEAR(SignedVolume(doubled), 0.06 * 8.0, 1e-6);
}

TEST(LoadMeshFile, LinesAreLeftOut) {
  const TriangleMesh m = LoadMeshFile(DataPath("meshes/triangle_and_line.obj"), 1.0);
  ASSERT_EQ(m.NumTriangles(), 1u);
  EXPECT_NEAR(m.AreaNormal(0).z(), 1.0, 1e-12);
  for (const auto& v : m.vertices) EXPECT_EQ(v.z(), 0.0);
}

TEST(LoadMeshFile, ErrorsNameTheFileAndTheProblem) {
  struct Case {
    std::string file;
    double scale;
    std::string problem;
  };
  const std::vector<Case> cases = {
      {"meshes/does_not_exist.stl", 1.0, "mesh file not found"},
      {"meshes/degenerate.stl", 1.0, "triangle 1 is degenerate"},
      {"meshes/no_faces.obj", 1.0, "degenerate mesh: mesh has no triangles"},
      {"meshes/garbage.stl", 1.0, "cannot read mesh"},
      {"meshes/ramp.stl", 0.0, "expected a positive finite mesh scale, got 0"},
      {"meshes/ramp.stl", -1.0, "expected a positive finite mesh scale, got -1"},
      {"with_meshes.yaml", 1.0, "expected an .stl, .obj or .ply mesh file, got extension '.yaml'"},
  };
  for (const Case& c : cases) {
    const std::string message = LoadError(DataPath(c.file), c.scale);
    EXPECT_NE(message.find(DataPath(c.file) + ": "), std::string::npos) << message;
    EXPECT_NE(message.find(c.problem), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace rbcp
