#include "rbcp/controller/swing_trajectory.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

constexpr int kSamples = 40;
constexpr double kMaxRise = 0.3;     // [m] highest extra lift tried
constexpr double kRiseStep = 0.02;   // [m]
constexpr double kRiseEnd = 0.4;     // the height reaches the apex over s in [0, kRiseEnd] (and back)
constexpr double kCrossBegin = 0.2;  // the horizontal motion runs over s in [kCrossBegin, 1 - kCrossBegin]
constexpr double kEndSkip = 0.97;    // beyond this the path dips below the foothold on purpose

double SmoothStep(double u, double* rate = nullptr) {
  if (u <= 0.0 || u >= 1.0) {
    if (rate) *rate = 0.0;
    return u <= 0.0 ? 0.0 : 1.0;
  }
  if (rate) *rate = 6.0 * u * (1.0 - u);
  return u * u * (3.0 - 2.0 * u);
}

/// Highest terrain within `radius` of xy (centre and eight points on the circle), or nullopt.
std::optional<double> TerrainTop(const TriangleMesh& terrain, const Eigen::Vector2d& xy, double radius) {
  std::optional<double> top;
  for (int k = -1; k < 8; ++k) {
    const double a = k * M_PI / 4.0;
    const Eigen::Vector2d p = k < 0 ? xy : Eigen::Vector2d(xy + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
    const std::optional<double> h = TerrainHeightAt(terrain, p);
    if (h && (!top || *h > *top)) top = h;
  }
  return top;
}

}  // namespace

Eigen::Vector3d SwingTrajectory::At(double s, Eigen::Vector3d* ds) const {
  double h_rate = 0.0;
  const double h = SmoothStep((s - kCrossBegin) / (1.0 - 2.0 * kCrossBegin), &h_rate);
  h_rate /= (1.0 - 2.0 * kCrossBegin);
  Eigen::Vector3d p;
  p.head<2>() = start_.head<2>() + h * (end_.head<2>() - start_.head<2>());
  double z_rate = 0.0;
  if (s <= 0.5) {
    double r = 0.0;
    p.z() = start_.z() + (apex_z_ - start_.z()) * SmoothStep(s / kRiseEnd, &r);
    z_rate = (apex_z_ - start_.z()) * r / kRiseEnd;
  } else {
    double r = 0.0;
    p.z() = end_.z() + (apex_z_ - end_.z()) * SmoothStep((1.0 - s) / kRiseEnd, &r);
    z_rate = -(apex_z_ - end_.z()) * r / kRiseEnd;
  }
  if (ds) {
    ds->head<2>() = h_rate * (end_.head<2>() - start_.head<2>());
    ds->z() = z_rate;
  }
  return p;
}

SwingTrajectory SwingTrajectory::Plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                                      const TriangleMesh* terrain, double foot_radius_m, const SwingConfig& config,
                                      const LegCheck& leg_clear) {
  SwingTrajectory s;
  s.start_ = start_W;
  s.end_ = target_W - Eigen::Vector3d(0, 0, config.touchdown_depth_m);
  const double base_apex = std::max(start_W.z(), target_W.z()) + config.height_m;
  s.apex_z_ = base_apex;
  s.clearance_m_ = std::numeric_limits<double>::infinity();
  const bool check_terrain = terrain != nullptr && !terrain->triangles.empty();
  if (check_terrain || leg_clear) {
    std::optional<SwingTrajectory> best;
    for (double rise = 0.0; rise <= kMaxRise + 1e-9; rise += kRiseStep) {
      SwingTrajectory c = s;
      c.apex_z_ = base_apex + rise;
      double middle = std::numeric_limits<double>::infinity();
      bool enters = false;
      for (int k = 1; k < kSamples; ++k) {
        const double u = static_cast<double>(k) / kSamples;
        if (u > kEndSkip) break;
        const Eigen::Vector3d p = c.At(u);
        if (check_terrain) {
          const std::optional<double> top = TerrainTop(*terrain, p.head<2>(), foot_radius_m);
          if (top) {
            // Away from its footholds the foot keeps the clearance; next to them it only must
            // not touch the terrain (it rises from and descends to a surface there).
            const double gap = p.z() - *top;
            const double near = foot_radius_m + 0.02;
            const bool away = (p.head<2>() - c.start_.head<2>()).norm() > near &&
                              (p.head<2>() - target_W.head<2>()).norm() > near;
            if (away) middle = std::min(middle, gap);
            if (gap < 0.005 && !(u > 1.0 - kRiseEnd && !away)) enters = true;
          }
        }
        if (leg_clear && k % 2 == 0 && !leg_clear(p)) c.leg_collisions_ += 1;
      }
      c.clearance_m_ = middle;
      const bool terrain_ok = !enters && middle >= config.terrain_clearance_m;
      if (terrain_ok && c.leg_collisions_ == 0) {
        best = c;
        break;
      }
      if (terrain_ok && (!best || c.leg_collisions_ <= best->leg_collisions_)) best = c;
    }
    if (best) {
      s = *best;
    } else {
      s.apex_z_ = base_apex + kMaxRise;
    }
  }
  // Duration from the path length: up, across, down.
  const double length = (s.apex_z_ - s.start_.z()) + (s.end_.head<2>() - s.start_.head<2>()).norm() +
                        (s.apex_z_ - s.end_.z());
  s.duration_s_ = std::max(config.min_duration_s, length / config.speed_mps);
  return s;
}

double SwingTrajectory::Phase(double t) const { return std::clamp(t / duration_s_, 0.0, 1.0); }

Eigen::Vector3d SwingTrajectory::Position(double t) const { return At(Phase(t)); }

Eigen::Vector3d SwingTrajectory::Velocity(double t) const {
  if (t <= 0.0 || t >= duration_s_) return Eigen::Vector3d::Zero();
  Eigen::Vector3d ds;
  At(Phase(t), &ds);
  return ds / duration_s_;
}

}  // namespace rbcp
