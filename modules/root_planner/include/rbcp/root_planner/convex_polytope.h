#pragma once
/// Convex polytopes as triangle meshes: convex hulls (Qhull), simplification, scaling, OBJ files.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "rbcp/core/triangle_mesh.h"

namespace rbcp {

/// A closed convex polytope: vertices and outward (counter-clockwise seen from outside) triangles.
struct ConvexPolytope {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;

  /// Enclosed volume [m^3].
  double Volume() const;
  /// Centre of the enclosed volume.
  Eigen::Vector3d Centroid() const;
  /// Largest signed distance of p to the face planes: <= 0 inside, > 0 outside (for points
  /// outside it is a lower bound of the Euclidean distance).
  double PlaneDistance(const Eigen::Vector3d& p) const;
  /// Axis-aligned bounds: (min, max).
  std::pair<Eigen::Vector3d, Eigen::Vector3d> Bounds() const;
  /// The same polytope scaled by `factor` about `center`.
  ConvexPolytope Scaled(double factor, const Eigen::Vector3d& center) const;
  TriangleMesh ToMesh() const;
};

/// A convex polytope prepared for exact overlap tests with triangles by the separating axis
/// theorem: the polytope and a triangle are disjoint exactly when their projections are disjoint
/// on one of the polytope's face normals, the triangle's normal, or a cross product of a polytope
/// edge and a triangle edge. No allocation per test: a path planner makes millions of them.
class PolytopeTriangleTest {
 public:
  explicit PolytopeTriangleTest(const ConvexPolytope& polytope);
  /// True when the triangle (a, b, c), given in the polytope's frame, and the closed polytope
  /// share a point (touching counts). A degenerate triangle is tested as its segment or point.
  bool Overlaps(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) const;

 private:
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Eigen::Vector3d> face_normals_;  ///< unit, one per distinct face plane
  std::vector<double> face_offsets_;           ///< n.x <= offset inside
  std::vector<Eigen::Vector3d> edge_directions_;  ///< unit, one per direction (up to sign)
};

/// Convex hull of a point set with Qhull (triangulated facets). Throws InputError when the points
/// do not span a volume (fewer than four points, or all coplanar).
ConvexPolytope ConvexHull(const std::vector<Eigen::Vector3d>& points);

/// An inner approximation of the hull of `points` with at most `max_triangles` triangles: the
/// hull of a subset of the hull vertices, grown greedily by the vertex farthest outside the
/// current approximation until that distance is at most `tolerance` [m] or the next vertex would
/// exceed the triangle budget. Deterministic.
ConvexPolytope SimplifiedConvexHull(const std::vector<Eigen::Vector3d>& points, int max_triangles, double tolerance);

/// Writes an OBJ file ("v x y z" and "f i j k" lines, 1-based) preceded by "# " comment lines.
/// Throws InputError when the file cannot be written.
void SaveObj(const ConvexPolytope& polytope, const std::string& path, const std::vector<std::string>& comments = {});

/// Reads an OBJ file written by SaveObj (or any OBJ with "v" and triangular "f" lines). Throws
/// InputError naming the file and line on malformed input, and when the shape is not closed and
/// convex (every vertex on the inner side of every face plane, within 1e-6 m).
ConvexPolytope LoadConvexObj(const std::string& path);

}  // namespace rbcp
