#include "surface_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/core/error.h"

namespace rbcp::contact_planner_detail {
namespace {

Eigen::Vector3d ClosestPointOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double s = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + s * ab;
}

}  // namespace

ConvexPolygon3d::ConvexPolygon3d(std::vector<Eigen::Vector3d> vertices, const Eigen::Vector3d& normal)
    : vertices_(std::move(vertices)), normal_(normal.normalized()) {
  RBCP_CHECK(vertices_.size() >= 3, "a contact surface needs at least three vertices");
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& v : vertices_) centroid += v;
  centroid /= static_cast<double>(vertices_.size());
  offset_ = normal_.dot(centroid);
  Eigen::Vector3d area_normal = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    area_normal += vertices_[i].cross(vertices_[(i + 1) % vertices_.size()]);
  }
  if (area_normal.dot(normal_) < 0.0) std::reverse(vertices_.begin(), vertices_.end());
  min_xy_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  max_xy_ = -min_xy_;
  for (const auto& v : vertices_) {
    min_xy_ = min_xy_.cwiseMin(v.head<2>());
    max_xy_ = max_xy_.cwiseMax(v.head<2>());
  }
}

Eigen::Vector3d ConvexPolygon3d::ClosestPoint(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = p - PlaneDistance(p) * normal_;
  bool inside = true;
  const std::size_t n = vertices_.size();
  for (std::size_t i = 0; i < n && inside; ++i) {
    const Eigen::Vector3d& a = vertices_[i];
    const Eigen::Vector3d& b = vertices_[(i + 1) % n];
    if ((b - a).cross(q - a).dot(normal_) < 0.0) inside = false;
  }
  if (inside) return q;
  Eigen::Vector3d best = vertices_[0];
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d c = ClosestPointOnSegment(vertices_[i], vertices_[(i + 1) % n], q);
    const double d2 = (c - q).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = c;
    }
  }
  return best;
}

bool ConvexPolygon3d::Contains(const Eigen::Vector3d& p, double plane_tolerance, double edge_tolerance) const {
  if (std::abs(PlaneDistance(p)) > plane_tolerance) return false;
  const std::size_t n = vertices_.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = vertices_[i];
    const Eigen::Vector3d e = vertices_[(i + 1) % n] - a;
    const double len = e.norm();
    if (len <= 0.0) continue;
    // Signed distance of p to the edge line inside the plane, positive inside.
    if (e.cross(p - a).dot(normal_) / len < -edge_tolerance) return false;
  }
  return true;
}

std::optional<Eigen::Vector3d> ConvexPolygon3d::PointAt(const Eigen::Vector2d& xy) const {
  if (std::abs(normal_.z()) < 1e-6) return std::nullopt;
  const double z = (offset_ - normal_.x() * xy.x() - normal_.y() * xy.y()) / normal_.z();
  return Eigen::Vector3d(xy.x(), xy.y(), z);
}

std::vector<Eigen::Vector3d> ConvexPolygon3d::ClipToSquare(const Eigen::Vector2d& centre_xy, double half) const {
  return ClipToRectangle(centre_xy, Eigen::Vector2d::UnitX(), half, half);
}

std::vector<Eigen::Vector3d> ConvexPolygon3d::ClipToRectangle(const Eigen::Vector2d& centre_xy,
                                                              const Eigen::Vector2d& axis_x, double half_x,
                                                              double half_y) const {
  std::vector<Eigen::Vector3d> poly = vertices_;
  std::vector<Eigen::Vector3d> next;
  const Eigen::Vector2d axis_y(-axis_x.y(), axis_x.x());
  // Half-planes n . (p - centre) <= h.
  const std::array<std::pair<Eigen::Vector2d, double>, 4> planes = {
      {{axis_x, half_x}, {-axis_x, half_x}, {axis_y, half_y}, {-axis_y, half_y}}};
  for (const auto& [n, h] : planes) {
    next.clear();
    const std::size_t count = poly.size();
    for (std::size_t i = 0; i < count; ++i) {
      const Eigen::Vector3d& a = poly[i];
      const Eigen::Vector3d& b = poly[(i + 1) % count];
      const double da = n.dot(a.head<2>() - centre_xy) - h;
      const double db = n.dot(b.head<2>() - centre_xy) - h;
      if (da <= 0.0) next.push_back(a);
      if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) next.push_back(a + (da / (da - db)) * (b - a));
    }
    poly.swap(next);
    if (poly.size() < 3) return {};
  }
  // Drop repeated vertices and check the area.
  next.clear();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    if ((poly[i] - poly[(i + 1) % poly.size()]).norm() > 1e-9) next.push_back(poly[i]);
  }
  if (next.size() < 3) return {};
  Eigen::Vector3d area_normal = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < next.size(); ++i) area_normal += next[i].cross(next[(i + 1) % next.size()]);
  if (0.5 * std::abs(area_normal.dot(normal_)) < 1e-8) return {};
  return next;
}

}  // namespace rbcp::contact_planner_detail
