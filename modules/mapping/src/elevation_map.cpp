#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

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

namespace {

/// Rounds of hole filling: a hole of up to two cells across closes.
constexpr int kFillPasses = 2;

/// Snaps the regions of `heights` (an n x n grid, NaN unknown) that are planes within the noise
/// onto their least-squares planes, seeded in cell order (deterministic) at planar patches.
void SnapPlanes(std::vector<float>& heights, int n, const ElevationMapConfig& config) {
  if (config.plane_step_m <= 0.0) return;
  struct Plane {
    double a, b, c, mx, my;  ///< z = a (ix - mx) + b (iy - my) + c
    double At(int ix, int iy) const { return a * (ix - mx) + b * (iy - my) + c; }
  };
  std::vector<Plane> planes;
  std::vector<int> plane_of;  ///< per region: its plane in `planes`, or -1
  const auto flat = [n](int ix, int iy) { return static_cast<std::size_t>(iy) * static_cast<std::size_t>(n) + static_cast<std::size_t>(ix); };
  const double step = config.plane_step_m;
  // A seed is a cell in the middle of a planar patch: its 8 neighbours known and within half a
  // step of the patch's least-squares plane (level or tilted: a block lying at 15 degrees rises
  // about a centimetre per cell). Returns that plane, z = a dx + b dy + c about the seed.
  const auto planar_patch = [&](int cx, int cy) -> std::optional<Eigen::Vector3d> {
    double sum = 0.0, sum_x = 0.0, sum_y = 0.0;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int jx = cx + dx, jy = cy + dy;
        if (jx < 0 || jy < 0 || jx >= n || jy >= n) return std::nullopt;
        const float h = heights[flat(jx, jy)];
        if (std::isnan(h)) return std::nullopt;
        sum += h;
        sum_x += dx * h;
        sum_y += dy * h;
      }
    }
    // On the 3 x 3 grid the least-squares plane has these closed forms (sum of dx^2 is 6).
    const Eigen::Vector3d plane(sum_x / 6.0, sum_y / 6.0, sum / 9.0);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const double on = plane.x() * dx + plane.y() * dy + plane.z();
        if (std::abs(heights[flat(cx + dx, cy + dy)] - on) > 0.5 * step) return std::nullopt;
      }
    }
    return plane;
  };
  std::vector<int> region(heights.size(), -1);
  std::vector<int> cells;
  int next = 0;
  for (std::size_t seed = 0; seed < heights.size(); ++seed) {
    const int sx = static_cast<int>(seed % static_cast<std::size_t>(n)), sy = static_cast<int>(seed / static_cast<std::size_t>(n));
    if (region[seed] >= 0 || std::isnan(heights[seed])) continue;
    const std::optional<Eigen::Vector3d> patch = planar_patch(sx, sy);
    if (!patch) continue;
    // Grow over 8-neighbours (far from the sensor the returns of one surface may touch only at
    // corners) that step at most `step` off the plane's rise from the cell they join from and
    // lie within `step` of the region's plane so far (refitted as the region doubles), so that
    // blocks of nearly the same height, side by side, stay apart.
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atz = Eigen::Vector3d::Zero();
    Eigen::Vector3d fit = *patch;  // z = a (ix - sx) + b (iy - sy) + c
    std::size_t refit_at = 8;
    const auto add = [&](int c) {
      const Eigen::Vector3d row((c % n) - sx, (c / n) - sy, 1.0);
      ata += row * row.transpose();
      atz += row * static_cast<double>(heights[static_cast<std::size_t>(c)]);
    };
    cells.assign(1, static_cast<int>(seed));
    region[seed] = next;
    add(static_cast<int>(seed));
    for (std::size_t head = 0; head < cells.size(); ++head) {
      const int c = cells[head];
      const int cx = c % n, cy = c / n;
      const int nx[8] = {cx - 1, cx + 1, cx, cx, cx - 1, cx + 1, cx - 1, cx + 1};
      const int ny[8] = {cy, cy, cy - 1, cy + 1, cy - 1, cy - 1, cy + 1, cy + 1};
      for (int k = 0; k < 8; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= n || ny[k] >= n) continue;
        const std::size_t j = flat(nx[k], ny[k]);
        if (region[j] >= 0 || std::isnan(heights[j])) continue;
        const double rise = fit.x() * (nx[k] - cx) + fit.y() * (ny[k] - cy);
        if (std::abs(heights[j] - heights[static_cast<std::size_t>(c)] - rise) > step) continue;
        const double on_fit = fit.x() * (nx[k] - sx) + fit.y() * (ny[k] - sy) + fit.z();
        if (std::abs(heights[j] - on_fit) > step) continue;
        region[j] = next;
        cells.push_back(static_cast<int>(j));
        add(static_cast<int>(j));
      }
      if (cells.size() >= refit_at) {
        const Eigen::Vector3d refit = ata.ldlt().solve(atz);
        if (refit.allFinite()) fit = refit;
        refit_at *= 2;
      }
    }
    ++next;
    plane_of.push_back(-1);
    if (static_cast<int>(cells.size()) < config.plane_min_cells) continue;
    const Eigen::Vector3d plane = ata.ldlt().solve(atz);
    if (!plane.allFinite()) continue;
    const auto on_plane = [&](int c) { return plane.x() * ((c % n) - sx) + plane.y() * ((c / n) - sy) + plane.z(); };
    double sq = 0.0;
    for (int c : cells) sq += std::pow(heights[static_cast<std::size_t>(c)] - on_plane(c), 2);
    if (std::sqrt(sq / static_cast<double>(cells.size())) > config.plane_max_rms_m) continue;
    for (int c : cells) heights[static_cast<std::size_t>(c)] = static_cast<float>(on_plane(c));
    plane_of.back() = static_cast<int>(planes.size());
    planes.push_back({plane.x(), plane.y(), plane.z(), static_cast<double>(sx), static_cast<double>(sy)});
  }
  // Holes between the returns of a plane (far from the sensor, rays fall more than a cell apart)
  // are that plane: an unknown cell with enough neighbours on one plane joins it.
  if (config.mesh_fill_neighbours > 8) return;
  for (int pass = 0; pass < kFillPasses; ++pass) {
    std::vector<std::pair<std::size_t, int>> fills;  // cell, region
    for (int iy = 0; iy < n; ++iy) {
      for (int ix = 0; ix < n; ++ix) {
        const std::size_t i = flat(ix, iy);
        if (!std::isnan(heights[i])) continue;
        int best_region = -1, best_count = 0;
        int seen[8];
        int count[8];
        int kinds = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int jx = ix + dx, jy = iy + dy;
            if ((dx == 0 && dy == 0) || jx < 0 || jy < 0 || jx >= n || jy >= n) continue;
            const int r = region[flat(jx, jy)];
            if (r < 0 || plane_of[static_cast<std::size_t>(r)] < 0) continue;
            int k = 0;
            while (k < kinds && seen[k] != r) ++k;
            if (k == kinds) {
              seen[kinds] = r;
              count[kinds++] = 0;
            }
            if (++count[k] > best_count) {
              best_count = count[k];
              best_region = r;
            }
          }
        }
        if (best_count >= config.mesh_fill_neighbours) fills.emplace_back(i, best_region);
      }
    }
    if (fills.empty()) break;
    for (const auto& [i, r] : fills) {
      const Plane& p = planes[static_cast<std::size_t>(plane_of[static_cast<std::size_t>(r)])];
      heights[i] = static_cast<float>(p.At(static_cast<int>(i % static_cast<std::size_t>(n)), static_cast<int>(i / static_cast<std::size_t>(n))));
      region[i] = r;
    }
  }
}

}  // namespace

std::vector<float> ElevationMap::MeshHeights() const {
  std::vector<float> out(height_.size(), kUnknown);
  const double step = config_.mesh_smoothing_step_m;
  for (int iy = 0; iy < n_; ++iy) {
    for (int ix = 0; ix < n_; ++ix) {
      const float h = height_[Flat(ix, iy)];
      if (std::isnan(h)) continue;
      if (step <= 0.0) {
        out[Flat(ix, iy)] = h;
        continue;
      }
      // Edge-preserving: only neighbours of the same surface (within step) count, by their weight.
      double weight = 0.0, sum = 0.0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int jx = ix + dx, jy = iy + dy;
          if (jx < 0 || jy < 0 || jx >= n_ || jy >= n_) continue;
          const float hn = height_[Flat(jx, jy)];
          if (std::isnan(hn) || std::abs(hn - h) > step) continue;
          const double w = 1.0 / std::max<double>(variance_[Flat(jx, jy)], config_.min_variance_m2);
          weight += w;
          sum += w * hn;
        }
      }
      out[Flat(ix, iy)] = static_cast<float>(sum / weight);
    }
  }
  SnapPlanes(out, n_, config_);
  return out;
}

TriangleMesh ElevationMap::MeshOf(const std::vector<float>& heights) const {
  TriangleMesh mesh;
  RBCP_CHECK(heights.size() == height_.size(), "one height per cell");
  if (!placed_ || known_ == 0) return mesh;
  const auto known = [&](int ix, int iy) { return !std::isnan(heights[Flat(ix, iy)]); };
  // Vertex of a cell, made the first time a triangle uses it (only used cells become vertices).
  std::vector<int> vertex(height_.size(), -1);
  const auto v = [&](int ix, int iy) {
    int& id = vertex[Flat(ix, iy)];
    if (id < 0) {
      const Eigen::Vector2d c = CellCentre(ix, iy);
      id = static_cast<int>(mesh.vertices.size());
      mesh.vertices.emplace_back(c.x(), c.y(), static_cast<double>(heights[Flat(ix, iy)]));
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
