#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/core/error.h"
#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping {

namespace {
constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();
/// How far (in cells) a cell's support distance grows with each measurement of another surface
/// that it turns away.
constexpr float kSupportGrowth = 0.1f;
}  // namespace

ElevationMap::ElevationMap(const ElevationMapConfig& config) : config_(config) {
  ValidateConfig(config_, "ElevationMapConfig");
  n_ = static_cast<int>(std::lround(config_.window_m / config_.resolution_m));
  const std::size_t cells = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
  height_.assign(cells, kUnknown);
  variance_.assign(cells, 0.0f);
  support_.assign(cells, 0.0f);
}

void ElevationMap::Recenter(const Eigen::Vector2d& xy) {
  if (!xy.allFinite()) throw InputError("ElevationMap::Recenter: expected a finite position, got a NaN or inf");
  const double r = config_.resolution_m;
  if (placed_) {
    const Eigen::Vector2d centre = origin_ + Eigen::Vector2d::Constant(0.5 * n_ * r);
    if ((xy - centre).norm() <= config_.recenter_distance_m) return;
  }
  // The cell holding xy becomes the window's middle cell.
  const std::int64_t new_ix = static_cast<std::int64_t>(std::floor(xy.x() / r)) - n_ / 2;
  const std::int64_t new_iy = static_cast<std::int64_t>(std::floor(xy.y() / r)) - n_ / 2;
  if (placed_) {
    const std::int64_t dx = new_ix - origin_ix_;
    const std::int64_t dy = new_iy - origin_iy_;
    if (dx == 0 && dy == 0) return;
    // New cell (ix, iy) is old cell (ix + dx, iy + dy); cells with no old counterpart are unknown.
    std::vector<float> height(height_.size(), kUnknown);
    std::vector<float> variance(variance_.size(), 0.0f);
    std::vector<float> support(support_.size(), 0.0f);
    known_ = 0;
    for (int iy = 0; iy < n_; ++iy) {
      const std::int64_t oy = iy + dy;
      if (oy < 0 || oy >= n_) continue;
      for (int ix = 0; ix < n_; ++ix) {
        const std::int64_t ox = ix + dx;
        if (ox < 0 || ox >= n_) continue;
        const std::size_t from = Flat(static_cast<int>(ox), static_cast<int>(oy));
        if (std::isnan(height_[from])) continue;
        height[Flat(ix, iy)] = height_[from];
        variance[Flat(ix, iy)] = variance_[from];
        support[Flat(ix, iy)] = support_[from];
        ++known_;
      }
    }
    height_.swap(height);
    variance_.swap(variance);
    support_.swap(support);
  }
  origin_ix_ = new_ix;
  origin_iy_ = new_iy;
  origin_ = Eigen::Vector2d(static_cast<double>(new_ix) * r, static_cast<double>(new_iy) * r);
  placed_ = true;
}

std::optional<std::pair<int, int>> ElevationMap::Index(const Eigen::Vector2d& xy) const {
  if (!placed_ || !xy.allFinite()) return std::nullopt;
  const double r = config_.resolution_m;
  // In cells of the world (as the origin is), so that a cell's bounds never depend on the window.
  const double fx = std::floor(xy.x() / r) - static_cast<double>(origin_ix_);
  const double fy = std::floor(xy.y() / r) - static_cast<double>(origin_iy_);
  if (fx < 0 || fy < 0 || fx >= n_ || fy >= n_) return std::nullopt;
  return std::make_pair(static_cast<int>(fx), static_cast<int>(fy));
}

Eigen::Vector2d ElevationMap::CellCentre(int ix, int iy) const {
  const double r = config_.resolution_m;
  return {(static_cast<double>(origin_ix_ + ix) + 0.5) * r, (static_cast<double>(origin_iy_ + iy) + 0.5) * r};
}

std::optional<Cell> ElevationMap::At(int ix, int iy) const {
  if (!placed_ || ix < 0 || iy < 0 || ix >= n_ || iy >= n_) return std::nullopt;
  const std::size_t i = Flat(ix, iy);
  if (std::isnan(height_[i])) return std::nullopt;
  return Cell{height_[i], variance_[i]};
}

std::optional<Cell> ElevationMap::At(const Eigen::Vector2d& xy) const {
  const auto index = Index(xy);
  if (!index) return std::nullopt;
  return At(index->first, index->second);
}

bool ElevationMap::Fuse(const Eigen::Vector3d& p, double variance) {
  if (!std::isfinite(p.z()) || !std::isfinite(variance)) return false;
  const auto index = Index(p.head<2>());
  if (!index) return false;
  const double offset = (p.head<2>() - CellCentre(index->first, index->second)).norm();
  const FuseOutcome outcome = FuseCell(index->first, index->second, p.z(), variance, offset);
  return outcome == FuseOutcome::kFused || outcome == FuseOutcome::kReplaced;
}

ElevationMap::FuseOutcome ElevationMap::FuseCell(int ix, int iy, double z, double variance, double offset_m,
                                                 bool gate) {
  if (ix < 0 || iy < 0 || ix >= n_ || iy >= n_) return FuseOutcome::kOutside;
  const std::size_t i = Flat(ix, iy);
  const float min_var = static_cast<float>(config_.min_variance_m2);
  const float var_p = std::max(static_cast<float>(variance), min_var);
  const float zf = static_cast<float>(z);
  const float offset = static_cast<float>(offset_m);
  float& h = height_[i];
  float& var_h = variance_[i];
  float& support = support_[i];
  if (std::isnan(h)) {
    h = zf;
    var_h = var_p;
    support = offset;
    ++known_;
    return FuseOutcome::kReplaced;
  }
  const float sum = var_h + var_p;
  const float limit = static_cast<float>(config_.gate_sigma) * std::sqrt(sum);
  const float d = zf - h;
  if (std::abs(d) > limit) {
    // Another surface than the estimate's. Above it: something new stands there, or a block's top
    // reaches into this cell; below it: a lower surface seen past an edge. It takes over when it
    // was measured nearer the centre, whose height the cell stands for (a foot always does).
    if (!gate || offset <= support) {
      h = zf;
      var_h = var_p;
      support = offset;
      return FuseOutcome::kReplaced;
    }
    // Turned away. Something new put down over the cell wins after a few measurements as the
    // support grows (something taken away is cleared by the rays through it instead).
    if (d > 0) support += kSupportGrowth * static_cast<float>(config_.resolution_m);
    return FuseOutcome::kGated;
  }
  h = (var_p * h + var_h * zf) / sum;
  var_h = std::max(var_h * var_p / sum, min_var);
  support = std::min(support, offset);
  return FuseOutcome::kFused;
}

void ElevationMap::Clear(int ix, int iy) {
  if (ix < 0 || iy < 0 || ix >= n_ || iy >= n_) return;
  const std::size_t i = Flat(ix, iy);
  if (std::isnan(height_[i])) return;
  height_[i] = kUnknown;
  variance_[i] = 0.0f;
  --known_;
}

std::size_t ElevationMap::MemoryBytes() const {
  return sizeof(*this) + (height_.capacity() + variance_.capacity() + support_.capacity()) * sizeof(float);
}

TriangleMesh ElevationMap::ToMesh() const {
  TriangleMesh mesh;
  if (!placed_ || known_ == 0) return mesh;
  const auto known = [&](int ix, int iy) { return !std::isnan(height_[Flat(ix, iy)]); };
  // Vertex of a cell, made the first time a triangle uses it (only used cells become vertices).
  std::vector<int> vertex(height_.size(), -1);
  const auto v = [&](int ix, int iy) {
    int& id = vertex[Flat(ix, iy)];
    if (id < 0) {
      const Eigen::Vector2d c = CellCentre(ix, iy);
      id = static_cast<int>(mesh.vertices.size());
      mesh.vertices.emplace_back(c.x(), c.y(), static_cast<double>(height_[Flat(ix, iy)]));
    }
    return id;
  };
  for (int iy = 0; iy + 1 < n_; ++iy) {
    for (int ix = 0; ix + 1 < n_; ++ix) {
      // a b c d: the block's corners counter-clockwise seen from above (x right, y up).
      const bool ka = known(ix, iy), kb = known(ix + 1, iy), kc = known(ix + 1, iy + 1), kd = known(ix, iy + 1);
      const int count = ka + kb + kc + kd;
      if (count < 3) continue;
      if (count == 4) {
        const int a = v(ix, iy), b = v(ix + 1, iy), c = v(ix + 1, iy + 1), d = v(ix, iy + 1);
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      } else if (!ka) {
        mesh.triangles.push_back({v(ix + 1, iy), v(ix + 1, iy + 1), v(ix, iy + 1)});
      } else if (!kb) {
        mesh.triangles.push_back({v(ix, iy), v(ix + 1, iy + 1), v(ix, iy + 1)});
      } else if (!kc) {
        mesh.triangles.push_back({v(ix, iy), v(ix + 1, iy), v(ix, iy + 1)});
      } else {
        mesh.triangles.push_back({v(ix, iy), v(ix + 1, iy), v(ix + 1, iy + 1)});
      }
    }
  }
  return mesh;
}

double PathCoverage(const ElevationMap& map, const std::vector<Eigen::Vector2d>& path, double radius_m) {
  if (path.empty()) return 0.0;
  const double r = map.resolution();
  const int reach = static_cast<int>(std::ceil(std::max(radius_m, 0.0) / r));
  std::size_t covered = 0;
  for (const Eigen::Vector2d& p : path) {
    const auto index = map.Index(p);
    bool all = index.has_value();
    // The cell under p, and every cell whose centre lies within radius_m of p.
    for (int dy = -reach; all && index && dy <= reach; ++dy) {
      for (int dx = -reach; all && dx <= reach; ++dx) {
        const int ix = index->first + dx, iy = index->second + dy;
        const bool inside = (dx == 0 && dy == 0) || (map.CellCentre(ix, iy) - p).norm() <= radius_m;
        if (inside && !map.At(ix, iy)) all = false;
      }
    }
    if (all) ++covered;
  }
  return static_cast<double>(covered) / static_cast<double>(path.size());
}

}  // namespace rbcp::mapping
