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

Eigen::Vector2d ClosestPointOnSegment2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double s = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + s * ab;
}

double Cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

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

std::optional<std::array<Eigen::Vector2d, 3>> ErodeTriangle(const std::array<Eigen::Vector2d, 3>& tri, double margin) {
  const double a = (tri[1] - tri[2]).norm();
  const double b = (tri[2] - tri[0]).norm();
  const double c = (tri[0] - tri[1]).norm();
  const double perimeter = a + b + c;
  const double area = 0.5 * std::abs(Cross2(tri[1] - tri[0], tri[2] - tri[0]));
  if (perimeter <= 0.0 || area <= 0.0) return std::nullopt;
  const double inradius = 2.0 * area / perimeter;
  if (inradius <= margin) return std::nullopt;
  const Eigen::Vector2d incentre = (a * tri[0] + b * tri[1] + c * tri[2]) / perimeter;
  const double scale = (inradius - margin) / inradius;
  std::array<Eigen::Vector2d, 3> out;
  for (int i = 0; i < 3; ++i) out[static_cast<std::size_t>(i)] = incentre + scale * (tri[static_cast<std::size_t>(i)] - incentre);
  return out;
}

Eigen::Vector2d ClosestPointInTriangle(const std::array<Eigen::Vector2d, 3>& tri, const Eigen::Vector2d& p) {
  const double orientation = Cross2(tri[1] - tri[0], tri[2] - tri[0]) >= 0.0 ? 1.0 : -1.0;
  bool inside = true;
  for (std::size_t i = 0; i < 3; ++i) {
    if (orientation * Cross2(tri[(i + 1) % 3] - tri[i], p - tri[i]) < 0.0) inside = false;
  }
  if (inside) return p;
  Eigen::Vector2d best = tri[0];
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 3; ++i) {
    const Eigen::Vector2d c = ClosestPointOnSegment2d(tri[i], tri[(i + 1) % 3], p);
    const double d2 = (c - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = c;
    }
  }
  return best;
}

}  // namespace rbcp::contact_planner_detail
