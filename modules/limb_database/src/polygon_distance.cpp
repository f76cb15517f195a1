#include "polygon_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/core/error.h"

namespace rbcp::limb_database_detail {

ConvexPolygonDistance::ConvexPolygonDistance(std::vector<Eigen::Vector3d> vertices, const Eigen::Vector3d& normal)
    : vertices_(std::move(vertices)) {
  const std::size_t n = vertices_.size();
  if (n < 3) throw InputError("surface polygon: expected at least 3 vertices, got " + std::to_string(n));
  for (const Eigen::Vector3d& v : vertices_) {
    if (!v.allFinite()) throw InputError("surface polygon: expected finite vertices, got a non-finite one");
  }
  if (!normal.allFinite() || normal.norm() < 1e-12) {
    throw InputError("surface polygon: expected a finite non-zero normal");
  }
  normal_ = normal.normalized();
  // Twice the signed area about the normal tells the winding.
  Eigen::Vector3d area_normal = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) area_normal += vertices_[i].cross(vertices_[(i + 1) % n]);
  const double signed_area2 = area_normal.dot(normal_);
  min_ = max_ = vertices_[0];
  for (const Eigen::Vector3d& v : vertices_) {
    min_ = min_.cwiseMin(v);
    max_ = max_.cwiseMax(v);
  }
  if (std::abs(signed_area2) < 1e-14) return;  // Degenerate()
  const double winding = signed_area2 > 0.0 ? 1.0 : -1.0;
  inward_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    inward_[i] = winding * normal_.cross(vertices_[(i + 1) % n] - vertices_[i]);
  }
}

double ConvexPolygonDistance::Distance(const Eigen::Vector3d& p, Eigen::Vector3d* closest) const {
  RBCP_CHECK(!Degenerate(), "distance to a polygon without area");
  const double height = PlaneHeight(p);
  const Eigen::Vector3d p_plane = p - height * normal_;
  bool inside = true;
  for (std::size_t i = 0; i < vertices_.size() && inside; ++i) inside = (p_plane - vertices_[i]).dot(inward_[i]) >= 0.0;
  if (inside) {
    if (closest) *closest = p_plane;
    return std::abs(height);
  }
  // Outside the prism over the polygon the closest point lies on the boundary.
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_point = vertices_[0];
  const std::size_t n = vertices_.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = vertices_[i];
    const Eigen::Vector3d ab = vertices_[(i + 1) % n] - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector3d c = a + t * ab;
    const double d2 = (p - c).squaredNorm();
    if (d2 < best) {
      best = d2;
      best_point = c;
    }
  }
  if (closest) *closest = best_point;
  return std::sqrt(best);
}

}  // namespace rbcp::limb_database_detail
