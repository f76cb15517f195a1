#pragma once
/// Geometry of convex contact surfaces used by the contact planner (support triangles:
/// rbcp/equilibrium/support_polygon.h).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <vector>

namespace rbcp::contact_planner_detail {

/// A convex planar polygon in the world frame with its plane.
class ConvexPolygon3d {
 public:
  /// `vertices` in order around the boundary (either direction), `normal` the plane normal.
  ConvexPolygon3d(std::vector<Eigen::Vector3d> vertices, const Eigen::Vector3d& normal);

  const std::vector<Eigen::Vector3d>& Vertices() const { return vertices_; }
  const Eigen::Vector3d& Normal() const { return normal_; }
  /// Signed distance of p above the plane [m].
  double PlaneDistance(const Eigen::Vector3d& p) const { return normal_.dot(p) - offset_; }
  /// The point of the polygon closest to p.
  Eigen::Vector3d ClosestPoint(const Eigen::Vector3d& p) const;
  /// True when p lies within plane_tolerance of the plane and inside the polygon, edges
  /// widened by edge_tolerance.
  bool Contains(const Eigen::Vector3d& p, double plane_tolerance, double edge_tolerance) const;
  /// The point of the plane straight above or below xy, when the plane is not vertical.
  std::optional<Eigen::Vector3d> PointAt(const Eigen::Vector2d& xy) const;
  /// The part of the polygon whose x and y lie within `half` of centre_xy (vertices; fewer than
  /// three when nothing of positive area is left).
  std::vector<Eigen::Vector3d> ClipToSquare(const Eigen::Vector2d& centre_xy, double half) const;
  /// The part of the polygon whose x and y lie within the rectangle centred at centre_xy with
  /// unit axis `axis_x` (the other axis perpendicular, counter-clockwise) and half extents
  /// half_x, half_y (same convention as ClipToSquare).
  std::vector<Eigen::Vector3d> ClipToRectangle(const Eigen::Vector2d& centre_xy, const Eigen::Vector2d& axis_x,
                                               double half_x, double half_y) const;
  const Eigen::Vector2d& MinXy() const { return min_xy_; }
  const Eigen::Vector2d& MaxXy() const { return max_xy_; }

 private:
  std::vector<Eigen::Vector3d> vertices_;  ///< counter-clockwise seen from the normal
  Eigen::Vector3d normal_;
  double offset_ = 0.0;
  Eigen::Vector2d min_xy_, max_xy_;
};

}  // namespace rbcp::contact_planner_detail
