#include <gtest/gtest.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <fstream>

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

void WriteFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(LoadMeshFile, DeclaredCountsBeyondTheFileAreRejectedBeforeAllocating) {
  test::ScratchDir dir;
  // A PLY of a few hundred bytes declaring four billion vertices.
  const auto ply = dir.path() / "huge.ply";
  WriteFile(ply,
            "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                std::string(64, '\0'));
  EXPECT_EQ(LoadError(ply.string(), 1.0),
            ply.string() + ": the PLY header declares 4000000000 vertex elements, more than the file's 64 bytes "
                           "after the header hold");
  // The same in ASCII.
  const auto ascii = dir.path() / "huge_ascii.ply";
  WriteFile(ascii, "ply\nformat ascii 1.0\nelement vertex 3000000000\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n0 0 0\n");
  EXPECT_NE(LoadError(ascii.string(), 1.0).find("declares 3000000000 vertex elements"), std::string::npos);
  // A binary STL declaring 2^32 - 1 triangles with one in the file.
  std::string stl(84 + 50, '\0');
  stl.replace(0, 6, "binary");
  for (int i = 80; i < 84; ++i) stl[static_cast<std::size_t>(i)] = '\xff';
  const auto big_stl = dir.path() / "huge.stl";
  WriteFile(big_stl, stl);
  EXPECT_EQ(LoadError(big_stl.string(), 1.0), big_stl.string() +
                                                  ": the binary STL declares 4294967295 triangles (214748364834 "
                                                  "bytes), the file has 134");
}

TEST(LoadMeshFile, APlyListLongerThanTheFileHoldsIsRejectedBeforeAllocating) {
  test::ScratchDir dir;
  const std::string header = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list int int vertex_indices\nend_header\n";
  // Binary: a face whose int count claims two billion indices, three in the file.
  std::string body(3 * 12, '\0');
  body += std::string("\x7f\xff\xff\xff", 4) + std::string(12, '\0');
  const auto binary = dir.path() / "long_list.ply";
  WriteFile(binary, "ply\nformat binary_big_endian 1.0\n" + header + body);
  EXPECT_EQ(LoadError(binary.string(), 1.0),
            binary.string() + ": face element 0 has a list of 2147483647 values, more than the file's remaining 12 "
                              "bytes hold");
  // A signed count with its top bit set is a negative length.
  body[36] = '\xff';
  WriteFile(binary, "ply\nformat binary_big_endian 1.0\n" + header + body);
  EXPECT_EQ(LoadError(binary.string(), 1.0), binary.string() + ": face element 0 has a list of negative length");
  // ASCII: the count must be the number of values on its line.
  const auto ascii = dir.path() / "long_list_ascii.ply";
  WriteFile(ascii, "ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n0 1 0\n555555555 0 1 2\n");
  EXPECT_EQ(LoadError(ascii.string(), 1.0), ascii.string() + ": the PLY body's line 4 (face element 0): a list of "
                                                             "555555555 values holds 3");
  WriteFile(ascii, "ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n");
  EXPECT_EQ(LoadError(ascii.string(), 1.0), ascii.string() + ": the PLY body's line 4 (face element 0): 5 values, "
                                                             "the element's properties take 4");
  WriteFile(ascii, "ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n" + std::string(20, ' ') + "\n");
  EXPECT_EQ(LoadError(ascii.string(), 1.0),
            ascii.string() + ": the PLY body ends after 2 of the 3 vertex elements the header declares");
  WriteFile(ascii, "ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 " + std::string(1, '\0') +
                       "2\n");
  EXPECT_EQ(LoadError(ascii.string(), 1.0), ascii.string() + ": the PLY body's line 4 holds the byte 0, expected "
                                                             "printable text");
  // The same file, well formed, loads.
  WriteFile(ascii, "ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(LoadError(ascii.string(), 1.0), "no error");
  // A name starting with a digit: assimp would read it as the element count.
  WriteFile(ascii, "ply\nformat ascii 1.0\nelement 22222222i 0\nend_header\n");
  EXPECT_NE(LoadError(ascii.string(), 1.0).find("line 3 'element 22222222i 0': expected 'element NAME COUNT'"),
            std::string::npos)
      << LoadError(ascii.string(), 1.0);
  // An element without properties cannot be read at all.
  WriteFile(ascii, "ply\nformat ascii 1.0\nelement nothing 100000000000\n" + header + "0 0 0\n");
  EXPECT_EQ(LoadError(ascii.string(), 1.0),
            ascii.string() + ": the PLY header declares 100000000000 nothing elements without a property");
}

TEST(LoadMeshFile, AnObjMaterialLineOpensNoOtherFile) {
  test::ScratchDir dir;
  const auto secret = dir.path() / "secret.mtl";
  WriteFile(secret, "newmtl stone\nKd 0.5 0.5 0.5\n");
  const auto obj = dir.path() / "ramp.obj";
  WriteFile(obj, "mtllib secret.mtl\nusemtl stone\n" + test::ReadText(DataPath("meshes/ramp.obj")));
  // Every open of the material file shows up as an inotify event.
  const int watch = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  ASSERT_GE(watch, 0);
  ASSERT_GE(::inotify_add_watch(watch, secret.c_str(), IN_OPEN), 0);
  const TriangleMesh m = LoadMeshFile(obj.string(), 0.01);
  EXPECT_EQ(m.NumTriangles(), 8u);
  alignas(inotify_event) char events[4096];
  const ssize_t n = ::read(watch, events, sizeof(events));
  EXPECT_LT(n, 0) << "the loader opened " << secret;
  // The watch works: opening the file ourselves is seen.
  std::ifstream(secret).get();
  EXPECT_GT(::read(watch, events, sizeof(events)), 0);
  ::close(watch);
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
