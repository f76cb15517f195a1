#include "rbcp/core/triangle_mesh.h"

#include <cmath>
#include <sstream>

namespace rbcp {

void TriangleMesh::Append(const TriangleMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  // No exact reserve here: the vectors grow geometrically, so appending many small meshes (a
  // scenario of many boxes) takes time linear in the result.
  for (const auto& t : other.triangles) triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

void TriangleMesh::Transform(const Eigen::Isometry3d& T, double scale) {
  for (auto& v : vertices) v = T * (scale * v);
}

Eigen::Vector3d TriangleMesh::AreaNormal(std::size_t tri) const {
  const Eigen::Vector3d p0 = Corner(tri, 0);
  return (Corner(tri, 1) - p0).cross(Corner(tri, 2) - p0);
}

TriangleMesh MakeBoxMesh(const Eigen::Vector3d& size) {
  TriangleMesh m;
  const Eigen::Vector3d h = 0.5 * size;
  for (int i = 0; i < 8; ++i) {
    m.vertices.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  }
  // Two triangles per face, counter-clockwise seen from outside.
  m.triangles = {{0, 2, 3}, {0, 3, 1},   // -z
                 {4, 5, 7}, {4, 7, 6},   // +z
                 {0, 1, 5}, {0, 5, 4},   // -y
                 {2, 6, 7}, {2, 7, 3},   // +y
                 {0, 4, 6}, {0, 6, 2},   // -x
                 {1, 3, 7}, {1, 7, 5}};  // +x
  return m;
}

std::string ValidateMesh(const TriangleMesh& mesh, double min_area) {
  std::ostringstream os;
  if (mesh.triangles.empty()) return "mesh has no triangles";
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      os << "vertex " << i << " is not finite";
      return os.str();
    }
  }
  const int n = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int idx : mesh.triangles[t]) {
      if (idx < 0 || idx >= n) {
        os << "triangle " << t << " refers to vertex " << idx << " but the mesh has " << n << " vertices";
        return os.str();
      }
    }
    const double area = mesh.Area(t);
    if (!(area >= min_area)) {
      os << "triangle " << t << " is degenerate (area " << area << " m^2)";
      return os.str();
    }
  }
  return {};
}

}  // namespace rbcp
