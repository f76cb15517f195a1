#pragma once
/// The support polygon: the convex hull of the stance feet projected along gravity (world z).

#include <Eigen/Core>
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

}  // namespace rbcp
