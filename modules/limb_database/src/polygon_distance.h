#pragma once
// Euclidean distance from points to a convex planar polygon (the solid polygon, not its boundary).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace rbcp::limb_database_detail {

class ConvexPolygonDistance {
 public:
  /// `vertices` in order around the boundary (either direction), `normal` the plane normal (any
  /// length). The plane passes through the first vertex. Throws InputError for fewer than 3
  /// vertices, non-finite values or a zero normal. A polygon without area (collinear or repeated
  /// vertices) is accepted but Degenerate(), and Distance() must not be called on it.
  ConvexPolygonDistance(std::vector<Eigen::Vector3d> vertices, const Eigen::Vector3d& normal);

  /// Distance [m] from p to the polygon; *closest (optional) receives the closest polygon point.
  double Distance(const Eigen::Vector3d& p, Eigen::Vector3d* closest = nullptr) const;

  /// Signed distance [m] of p from the polygon's plane, along Normal().
  double PlaneHeight(const Eigen::Vector3d& p) const { return (p - vertices_[0]).dot(normal_); }
  /// Unit normal of the polygon's plane.
  const Eigen::Vector3d& Normal() const { return normal_; }

  /// True when the polygon has no area about the normal (less than 1e-14 m^2 twice over).
  bool Degenerate() const { return inward_.empty(); }

  /// Axis-aligned bounds of the vertices.
  const Eigen::Vector3d& Min() const { return min_; }
  const Eigen::Vector3d& Max() const { return max_; }

 private:
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Eigen::Vector3d> inward_;  // in-plane inward normal of edge i (vertex i to i + 1)
  Eigen::Vector3d normal_;               // unit
  Eigen::Vector3d min_;
  Eigen::Vector3d max_;
};

}  // namespace rbcp::limb_database_detail
