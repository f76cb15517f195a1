#include <algorithm>
#include <cmath>

#include "rbcp/scenario/scenario.h"

namespace rbcp {

std::optional<double> TerrainHeightAt(const TriangleMesh& mesh, const Eigen::Vector2d& xy) {
  // Barycentric slack: points on a shared edge belong to both triangles.
  constexpr double kInsideSlack = 1e-9;
  // Twice the projected area [m^2] below which a triangle counts as vertical.
  constexpr double kVerticalArea = 1e-14;
  std::optional<double> best;
  for (std::size_t t = 0; t < mesh.NumTriangles(); ++t) {
    const Eigen::Vector3d a = mesh.Corner(t, 0);
    const Eigen::Vector3d b = mesh.Corner(t, 1);
    const Eigen::Vector3d c = mesh.Corner(t, 2);
    const double d = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(d) < kVerticalArea) continue;
    const double px = xy.x() - a.x();
    const double py = xy.y() - a.y();
    const double w1 = (px * (c.y() - a.y()) - (c.x() - a.x()) * py) / d;
    const double w2 = ((b.x() - a.x()) * py - px * (b.y() - a.y())) / d;
    const double w0 = 1.0 - w1 - w2;
    if (w0 < -kInsideSlack || w1 < -kInsideSlack || w2 < -kInsideSlack) continue;
    const double z = w0 * a.z() + w1 * b.z() + w2 * c.z();
    if (!best || z > *best) best = z;
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
