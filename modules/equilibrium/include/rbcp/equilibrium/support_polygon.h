#pragma once
/// The support polygon: the convex hull of the stance feet projected along gravity (world z).

#include <Eigen/Core>
#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "rbcp/equilibrium/friction_cone.h"

namespace rbcp {

/// Counter-clockwise convex hull of the points' (x, y), without collinear vertices. Fewer than
/// three vertices when the points are all equal (one vertex) or collinear (the two extremes).
std::vector<Eigen::Vector2d> ConvexHull2d(std::vector<Eigen::Vector2d> points);

/// Signed distance [m] from (x, y) of com_W to the boundary of the convex hull of the feet's
/// (x, y): positive inside, negative outside, zero on the boundary. With the feet collinear or
/// coincident the hull has no inside and the result is minus the distance to it (at most 0).
/// Throws InputError when feet_W is empty.
double SupportPolygonMargin(const std::vector<Eigen::Vector3d>& feet_W, const Eigen::Vector3d& com_W);
double SupportPolygonMargin(const std::vector<ContactPoint>& contacts, const Eigen::Vector3d& com_W);

/// The centre of pressure of forces on the feet, and its signed distance inside their polygon
/// (SupportPolygonMargin) [m]. Both NaN unless three feet or more push with more than 1 N together.
struct CentreOfPressure {
  Eigen::Vector3d position = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  double margin_m = std::numeric_limits<double>::quiet_NaN();
};
/// The centre of pressure of `normal_force_N[i]` on `feet_W[i]` (negative forces count as zero).
/// Throws InputError when the two differ in size.
CentreOfPressure ComputeCentreOfPressure(const std::vector<Eigen::Vector3d>& feet_W,
                                         const std::vector<double>& normal_force_N);

/// The centre of the largest circle inside a triangle (a support triangle, say).
Eigen::Vector2d TriangleIncentre(const std::array<Eigen::Vector2d, 3>& tri);

/// The triangle shrunk inwards by `margin` (every point of the result is at least `margin` from
/// the original edges: a similar triangle about the incentre); nullopt when the inradius is not
/// larger than the margin.
std::optional<std::array<Eigen::Vector2d, 3>> ErodeTriangle(const std::array<Eigen::Vector2d, 3>& tri, double margin);

/// The point of the (solid) triangle closest to p.
Eigen::Vector2d ClosestPointInTriangle(const std::array<Eigen::Vector2d, 3>& tri, const Eigen::Vector2d& p);

}  // namespace rbcp
