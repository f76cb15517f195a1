#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/scenario/scenario.h"

namespace rbcp {

namespace {

// Barycentric slack: points on a shared edge belong to both triangles.
constexpr double kInsideSlack = 1e-9;
// [m] A point this far outside a triangle's xy bounds lies outside it even with the slack above.
constexpr double kBoundsSlack = 1e-6;
// Twice the projected area [m^2] below which a triangle counts as vertical.
constexpr double kVerticalArea = 1e-14;

/// Height of the triangle abc above xy, nullopt when xy lies outside its projection or it is vertical.
std::optional<double> HeightOver(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                 const Eigen::Vector2d& xy) {
  const double d = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  if (std::abs(d) < kVerticalArea) return std::nullopt;
  const double px = xy.x() - a.x();
  const double py = xy.y() - a.y();
  const double w1 = (px * (c.y() - a.y()) - (c.x() - a.x()) * py) / d;
  const double w2 = ((b.x() - a.x()) * py - px * (b.y() - a.y())) / d;
  const double w0 = 1.0 - w1 - w2;
  if (w0 < -kInsideSlack || w1 < -kInsideSlack || w2 < -kInsideSlack) return std::nullopt;
  return w0 * a.z() + w1 * b.z() + w2 * c.z();
}

}  // namespace

TerrainHeightMap::TerrainHeightMap(const TriangleMesh& mesh, double cell_m) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (std::size_t t = 0; t < mesh.NumTriangles(); ++t) {
    Triangle tri{mesh.Corner(t, 0), mesh.Corner(t, 1), mesh.Corner(t, 2), {}, {}};
    tri.lo = tri.a.head<2>().cwiseMin(tri.b.head<2>()).cwiseMin(tri.c.head<2>()).array() - kBoundsSlack;
    tri.hi = tri.a.head<2>().cwiseMax(tri.b.head<2>()).cwiseMax(tri.c.head<2>()).array() + kBoundsSlack;
    const double d = (tri.b.x() - tri.a.x()) * (tri.c.y() - tri.a.y()) - (tri.c.x() - tri.a.x()) * (tri.b.y() - tri.a.y());
    if (std::abs(d) < kVerticalArea || !tri.a.allFinite() || !tri.b.allFinite() || !tri.c.allFinite()) continue;
    triangles_.push_back(tri);
    for (const Eigen::Vector3d* p : {&tri.a, &tri.b, &tri.c}) {
      lo = lo.cwiseMin(p->head<2>());
      hi = hi.cwiseMax(p->head<2>());
    }
  }
  if (triangles_.empty()) return;
  constexpr double kMaxCells = 1e6;
  const Eigen::Vector2d extent = (hi - lo).cwiseMax(1e-6);
  cell_ = std::max({cell_m, 1e-3, std::sqrt(extent.x() * extent.y() / kMaxCells)});
  origin_ = lo;
  nx_ = static_cast<int>(std::floor(extent.x() / cell_)) + 1;
  ny_ = static_cast<int>(std::floor(extent.y() / cell_)) + 1;
  const auto cell_range = [&](const Triangle& t, int* x0, int* x1, int* y0, int* y1) {
    const Eigen::Vector2d a = t.a.head<2>(), b = t.b.head<2>(), c = t.c.head<2>();
    const Eigen::Vector2d tlo = (a.cwiseMin(b).cwiseMin(c) - origin_) / cell_;
    const Eigen::Vector2d thi = (a.cwiseMax(b).cwiseMax(c) - origin_) / cell_;
    // A point on a cell's edge may be looked up in either cell: take the neighbours too.
    *x0 = std::clamp(static_cast<int>(std::floor(tlo.x() - 1e-6)), 0, nx_ - 1);
    *x1 = std::clamp(static_cast<int>(std::floor(thi.x() + 1e-6)), 0, nx_ - 1);
    *y0 = std::clamp(static_cast<int>(std::floor(tlo.y() - 1e-6)), 0, ny_ - 1);
    *y1 = std::clamp(static_cast<int>(std::floor(thi.y() + 1e-6)), 0, ny_ - 1);
  };
  std::vector<int> counts(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
  int x0, x1, y0, y1;
  for (const Triangle& t : triangles_) {
    cell_range(t, &x0, &x1, &y0, &y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) counts[static_cast<std::size_t>(y * nx_ + x) + 1] += 1;
    }
  }
  for (std::size_t k = 1; k < counts.size(); ++k) counts[k] += counts[k - 1];
  cell_start_ = counts;
  cell_triangles_.resize(static_cast<std::size_t>(counts.back()));
  std::vector<int> fill(counts.begin(), counts.end() - 1);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    cell_range(triangles_[i], &x0, &x1, &y0, &y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) cell_triangles_[static_cast<std::size_t>(fill[static_cast<std::size_t>(y * nx_ + x)]++)] = static_cast<int>(i);
    }
  }
}

std::optional<double> TerrainHeightMap::At(const Eigen::Vector2d& xy) const {
  if (triangles_.empty() || !xy.allFinite()) return std::nullopt;
  const Eigen::Vector2d u = (xy - origin_) / cell_;
  const int x = static_cast<int>(std::floor(u.x()));
  const int y = static_cast<int>(std::floor(u.y()));
  // Beyond the grid by more than the edge slack: no triangle there.
  if (u.x() < -1e-6 || u.y() < -1e-6 || x > nx_ || y > ny_) return std::nullopt;
  const std::size_t k = static_cast<std::size_t>(std::clamp(y, 0, ny_ - 1) * nx_ + std::clamp(x, 0, nx_ - 1));
  std::optional<double> best;
  for (int i = cell_start_[k]; i < cell_start_[k + 1]; ++i) {
    const Triangle& t = triangles_[static_cast<std::size_t>(cell_triangles_[static_cast<std::size_t>(i)])];
    if (xy.x() < t.lo.x() || xy.y() < t.lo.y() || xy.x() > t.hi.x() || xy.y() > t.hi.y()) continue;
    const std::optional<double> z = HeightOver(t.a, t.b, t.c, xy);
    if (z && (!best || *z > *best)) best = z;
  }
  return best;
}

std::optional<double> TerrainHeightAt(const TriangleMesh& mesh, const Eigen::Vector2d& xy) {
  std::optional<double> best;
  for (std::size_t t = 0; t < mesh.NumTriangles(); ++t) {
    const std::optional<double> z = HeightOver(mesh.Corner(t, 0), mesh.Corner(t, 1), mesh.Corner(t, 2), xy);
    if (z && (!best || *z > *best)) best = z;
  }
  return best;
}

std::vector<std::size_t> FindCoveredUpwardTriangles(const TriangleMesh& mesh, double min_normal_z, double tolerance) {
  // Probe points: a barycentric grid pulled 10 % toward the centroid so that none lies on an edge,
  // where an abutting solid would count as covering.
  constexpr int kGrid = 8;
  constexpr double kPull = 0.9;
  std::vector<std::size_t> covered;
  for (std::size_t t = 0; t < mesh.NumTriangles(); ++t) {
    const Eigen::Vector3d n = mesh.AreaNormal(t);
    const double norm = n.norm();
    if (norm <= 0.0 || n.z() / norm < min_normal_z) continue;
    const Eigen::Vector3d a = mesh.Corner(t, 0);
    const Eigen::Vector3d b = mesh.Corner(t, 1);
    const Eigen::Vector3d c = mesh.Corner(t, 2);
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    bool is_covered = false;
    for (int i = 0; i <= kGrid && !is_covered; ++i) {
      for (int j = 0; i + j <= kGrid && !is_covered; ++j) {
        const double u = static_cast<double>(i) / kGrid;
        const double v = static_cast<double>(j) / kGrid;
        const Eigen::Vector3d p = centroid + kPull * ((1.0 - u - v) * a + u * b + v * c - centroid);
        const std::optional<double> top = TerrainHeightAt(mesh, p.head<2>());
        is_covered = top && *top > p.z() + tolerance;
      }
    }
    if (is_covered) covered.push_back(t);
  }
  return covered;
}

}  // namespace rbcp
