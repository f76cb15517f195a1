#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping {

namespace {

/// The truth's triangles bucketed by their xy bounding box in a uniform 2-D grid, so that a
/// vertical line meets only the few triangles of its bucket.
class VerticalProbe {
 public:
  explicit VerticalProbe(const TriangleMesh& mesh) : mesh_(mesh) {
    if (mesh.triangles.empty()) return;
    lo_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo_;
    for (const Eigen::Vector3d& v : mesh.vertices) {
      lo_ = lo_.cwiseMin(v.head<2>());
      hi = hi.cwiseMax(v.head<2>());
    }
    // About one triangle a bucket when they spread evenly; at most 1024 x 1024 buckets.
    const Eigen::Vector2d extent = (hi - lo_).cwiseMax(1e-9);
    const double side = std::sqrt(extent.x() * extent.y() / static_cast<double>(mesh.triangles.size()));
    cell_ = std::max({side, extent.maxCoeff() / 1024.0, 1e-6});
    nx_ = std::max(1, static_cast<int>(std::ceil(extent.x() / cell_)));
    ny_ = std::max(1, static_cast<int>(std::ceil(extent.y() / cell_)));
    // Counting sort of the triangles into buckets (two passes, one flat array).
    std::vector<int> count(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
    const auto each_bucket = [&](std::size_t t, auto&& f) {
      Eigen::Vector2d a = mesh.Corner(t, 0).head<2>(), b = a;
      for (int k = 1; k < 3; ++k) {
        a = a.cwiseMin(mesh.Corner(t, k).head<2>());
        b = b.cwiseMax(mesh.Corner(t, k).head<2>());
      }
      const int x0 = Clamp(a.x() - lo_.x(), nx_), x1 = Clamp(b.x() - lo_.x(), nx_);
      const int y0 = Clamp(a.y() - lo_.y(), ny_), y1 = Clamp(b.y() - lo_.y(), ny_);
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) f(static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_) + x);
      }
    };
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) each_bucket(t, [&](std::size_t b) { ++count[b + 1]; });
    for (std::size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
    start_ = count;
    items_.resize(static_cast<std::size_t>(count.back()));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      each_bucket(t, [&](std::size_t b) { items_[static_cast<std::size_t>(count[b]++)] = static_cast<int>(t); });
    }
  }

  /// The highest z of the mesh on the vertical line through xy; nullopt when it misses the mesh.
  std::optional<double> Top(const Eigen::Vector2d& xy) const {
    if (items_.empty()) return std::nullopt;
    const Eigen::Vector2d q = xy - lo_;
    if (q.x() < 0 || q.y() < 0 || q.x() > nx_ * cell_ || q.y() > ny_ * cell_) return std::nullopt;
    const std::size_t b = static_cast<std::size_t>(Clamp(q.y(), ny_)) * static_cast<std::size_t>(nx_) +
                          static_cast<std::size_t>(Clamp(q.x(), nx_));
    std::optional<double> top;
    for (int i = start_[b]; i < start_[b + 1]; ++i) {
      const std::size_t t = static_cast<std::size_t>(items_[static_cast<std::size_t>(i)]);
      const Eigen::Vector3d p0 = mesh_.Corner(t, 0), p1 = mesh_.Corner(t, 1), p2 = mesh_.Corner(t, 2);
      // Barycentric coordinates of xy in the triangle's projection (vertical triangles have none).
      const Eigen::Vector2d e1 = (p1 - p0).head<2>(), e2 = (p2 - p0).head<2>(), w = xy - p0.head<2>();
      const double det = e1.x() * e2.y() - e1.y() * e2.x();
      if (std::abs(det) < 1e-14) continue;
      const double u = (w.x() * e2.y() - w.y() * e2.x()) / det;
      const double v = (e1.x() * w.y() - e1.y() * w.x()) / det;
      constexpr double kEps = 1e-12;
      if (u < -kEps || v < -kEps || u + v > 1.0 + kEps) continue;
      const double z = p0.z() + u * (p1.z() - p0.z()) + v * (p2.z() - p0.z());
      if (!top || z > *top) top = z;
    }
    return top;
  }

 private:
  int Clamp(double offset, int n) const {
    return std::clamp(static_cast<int>(std::floor(offset / cell_)), 0, n - 1);
  }

  const TriangleMesh& mesh_;
  Eigen::Vector2d lo_ = Eigen::Vector2d::Zero();
  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<int> start_;  ///< bucket b holds items_[start_[b], start_[b + 1])
  std::vector<int> items_;
};

}  // namespace

HeightError MeasureHeightError(const ElevationMap& map, const TriangleMesh& truth) {
  const VerticalProbe probe(truth);
  HeightError out;
  std::vector<double> abs_error;
  double sum_sq = 0.0;
  // The points of a cell where the truth is probed: kSamples x kSamples, evenly inside the cell
  // (an odd count, so that its centre is one of them).
  constexpr int kSamples = 5;
  const double r = map.resolution();
  for (int iy = 0; iy < map.num_y(); ++iy) {
    for (int ix = 0; ix < map.num_x(); ++ix) {
      const auto cell = map.At(ix, iy);
      if (!cell) continue;
      const Eigen::Vector2d centre = map.CellCentre(ix, iy);
      std::optional<double> error;  // signed, the smallest in magnitude over the samples
      for (int sy = 0; sy < kSamples; ++sy) {
        for (int sx = 0; sx < kSamples; ++sx) {
          const Eigen::Vector2d offset((sx + 0.5) / kSamples - 0.5, (sy + 0.5) / kSamples - 0.5);
          const auto top = probe.Top(centre + r * offset);
          if (!top) continue;
          const double e = cell->height - *top;
          if (!error || std::abs(e) < std::abs(*error)) error = e;
        }
      }
      if (!error) {
        ++out.cells_no_truth;
        continue;
      }
      sum_sq += *error * *error;
      abs_error.push_back(std::abs(*error));
    }
  }
  out.cells = abs_error.size();
  if (abs_error.empty()) return out;
  out.rms_m = std::sqrt(sum_sq / static_cast<double>(abs_error.size()));
  out.max_m = *std::max_element(abs_error.begin(), abs_error.end());
  // The nearest-rank 95th percentile.
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(abs_error.size()))) - 1;
  std::nth_element(abs_error.begin(), abs_error.begin() + static_cast<long>(rank), abs_error.end());
  out.p95_m = abs_error[rank];
  return out;
}

}  // namespace rbcp::mapping
