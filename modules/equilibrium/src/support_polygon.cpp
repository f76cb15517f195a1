#include "rbcp/equilibrium/support_polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

double Cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

Eigen::Vector2d ClosestPointOnSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double s = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + s * ab;
}

double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (ClosestPointOnSegment(a, b, p) - p).norm();
}

}  // namespace

std::vector<Eigen::Vector2d> ConvexHull2d(std::vector<Eigen::Vector2d> pts) {
  // Andrew's monotone chain; drops collinear and duplicate points.
  std::sort(pts.begin(), pts.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  std::vector<Eigen::Vector2d> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && Cross(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && Cross(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);  // the last point repeats the first
  return hull;
}

double SupportPolygonMargin(const std::vector<Eigen::Vector3d>& feet_W, const Eigen::Vector3d& com_W) {
  if (feet_W.empty()) throw InputError("support polygon: expected at least one foot, got none");
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(feet_W.size());
  for (const auto& f : feet_W) xy.emplace_back(f.x(), f.y());
  const std::vector<Eigen::Vector2d> hull = ConvexHull2d(std::move(xy));
  const Eigen::Vector2d p(com_W.x(), com_W.y());
  if (hull.size() == 1) return -(hull[0] - p).norm();
  if (hull.size() == 2) return -SegmentDistance(p, hull[0], hull[1]);
  double dist = std::numeric_limits<double>::infinity();
  bool inside = true;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d& b = hull[(i + 1) % hull.size()];
    if (Cross(a, b, p) < 0.0) inside = false;  // right of a counter-clockwise edge
    dist = std::min(dist, SegmentDistance(p, a, b));
  }
  return inside ? dist : -dist;
}

CentreOfPressure ComputeCentreOfPressure(const std::vector<Eigen::Vector3d>& feet_W,
                                         const std::vector<double>& normal_force_N) {
  if (feet_W.size() != normal_force_N.size()) {
    throw InputError("centre of pressure: " + std::to_string(feet_W.size()) + " feet and " +
                     std::to_string(normal_force_N.size()) + " forces");
  }
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  double total_N = 0.0;
  for (std::size_t i = 0; i < feet_W.size(); ++i) {
    const double f = std::max(0.0, normal_force_N[i]);
    weighted += f * feet_W[i];
    total_N += f;
  }
  CentreOfPressure cop;
  if (feet_W.size() < 3 || !(total_N > 1.0)) return cop;
  cop.position = weighted / total_N;
  cop.margin_m = SupportPolygonMargin(feet_W, cop.position);
  return cop;
}

double SupportPolygonMargin(const std::vector<ContactPoint>& contacts, const Eigen::Vector3d& com_W) {
  std::vector<Eigen::Vector3d> feet;
  feet.reserve(contacts.size());
  for (const auto& c : contacts) feet.push_back(c.position);
  return SupportPolygonMargin(feet, com_W);
}

Eigen::Vector2d TriangleIncentre(const std::array<Eigen::Vector2d, 3>& tri) {
  const double a = (tri[1] - tri[2]).norm();
  const double b = (tri[2] - tri[0]).norm();
  const double c = (tri[0] - tri[1]).norm();
  const double perimeter = a + b + c;
  if (!(perimeter > 0.0)) return tri[0];
  return (a * tri[0] + b * tri[1] + c * tri[2]) / perimeter;
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
    const Eigen::Vector2d c = ClosestPointOnSegment(tri[i], tri[(i + 1) % 3], p);
    const double d2 = (c - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = c;
    }
  }
  return best;
}

}  // namespace rbcp
