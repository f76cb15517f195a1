#pragma once
/// A triangle soup with shared vertices: the common currency for terrain geometry.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

namespace rbcp {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;      ///< [m], in the frame the owner states (world for terrain)
  std::vector<std::array<int, 3>> triangles;  ///< vertex indices, counter-clockwise seen from outside

  std::size_t NumTriangles() const { return triangles.size(); }
  bool Empty() const { return triangles.empty(); }

  /// Appends another mesh, offsetting its indices.
  void Append(const TriangleMesh& other);
  /// Applies a rigid transform (and optional uniform scale first) to every vertex.
  void Transform(const Eigen::Isometry3d& T, double scale = 1.0);

  Eigen::Vector3d Corner(std::size_t tri, int k) const { return vertices[static_cast<std::size_t>(triangles[tri][static_cast<std::size_t>(k)])]; }
  /// Unnormalised normal (p1 - p0) x (p2 - p0); its norm is twice the area.
  Eigen::Vector3d AreaNormal(std::size_t tri) const;
  double Area(std::size_t tri) const { return 0.5 * AreaNormal(tri).norm(); }
};

/// A closed axis-aligned box of the given full size [m], centred at the origin, outward winding.
TriangleMesh MakeBoxMesh(const Eigen::Vector3d& size);

/// Checks the mesh is usable: at least one triangle, finite vertices, indices in range, and
/// no triangle with an area below min_area [m^2]. Returns an empty string when valid, otherwise
/// a description of the first problem ("triangle 12 is degenerate (area 0 m^2)").
std::string ValidateMesh(const TriangleMesh& mesh, double min_area = 1e-12);

}  // namespace rbcp
