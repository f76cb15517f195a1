#include "rbcp/controller/swing_trajectory.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

constexpr int kSamples = 40;
constexpr double kMaxRise = 0.3;      // [m] highest extra lift tried
constexpr double kRiseStep = 0.02;    // [m]
constexpr double kMiddleBegin = 0.2;  // the clearance is required over s in [begin, end]
constexpr double kMiddleEnd = 0.8;
constexpr double kEndSkip = 0.93;     // beyond this the path dips below the foothold on purpose

/// Highest terrain within `radius` of xy (centre and four points on the circle), or nullopt.
std::optional<double> TerrainTop(const TriangleMesh& terrain, const Eigen::Vector2d& xy, double radius) {
  std::optional<double> top;
  const Eigen::Vector2d offsets[] = {{0, 0}, {radius, 0}, {-radius, 0}, {0, radius}, {0, -radius}};
  for (const Eigen::Vector2d& o : offsets) {
    const std::optional<double> h = TerrainHeightAt(terrain, xy + o);
    if (h && (!top || *h > *top)) top = h;
  }
  return top;
}

double SmoothStep(double u) { return u * u * (3.0 - 2.0 * u); }
double SmoothStepRate(double u) { return 6.0 * u * (1.0 - u); }

}  // namespace

SwingTrajectory SwingTrajectory::Plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& start_normal,
                                      const Eigen::Vector3d& target_W, const Eigen::Vector3d& target_normal,
                                      const TriangleMesh* terrain, double foot_radius_m, const SwingConfig& config) {
  SwingTrajectory s;
  const Eigen::Vector3d n0 = start_normal.normalized();
  const Eigen::Vector3d n1 = target_normal.normalized();
  const Eigen::Vector3d end = target_W - config.touchdown_depth_m * n1;
  const double apex = std::max(start_W.z(), target_W.z()) + config.height_m;
  // A cubic Bezier with both inner points at height h above their ends peaks near 3h/4 above them.
  auto place = [&](double rise) {
    const double up0 = (apex + rise - start_W.z()) * 4.0 / 3.0;
    const double up1 = (apex + rise - end.z()) * 4.0 / 3.0;
    s.points_ = {start_W, start_W + up0 / std::max(n0.z(), 0.5) * n0, end + up1 / std::max(n1.z(), 0.5) * n1, end};
  };
  place(0.0);
  s.clearance_m_ = std::numeric_limits<double>::infinity();
  if (terrain != nullptr && !terrain->triangles.empty()) {
    for (double rise = 0.0; rise <= kMaxRise + 1e-9; rise += kRiseStep) {
      place(rise);
      double middle = std::numeric_limits<double>::infinity();
      bool enters = false;
      for (int k = 1; k < kSamples; ++k) {
        const double u = static_cast<double>(k) / kSamples;
        if (u > kEndSkip) break;
        const Eigen::Vector3d p = s.Bezier(u);
        const std::optional<double> top = TerrainTop(*terrain, p.head<2>(), foot_radius_m);
        if (!top) continue;
        const double gap = p.z() - *top;
        if (u >= kMiddleBegin && u <= kMiddleEnd) middle = std::min(middle, gap);
        // Near the ends the foot rises from (or descends to) its own foothold: only require that
        // it does not sink into terrain higher than that foothold.
        if (gap < -1e-3) enters = true;
      }
      s.clearance_m_ = middle;
      if (!enters && middle >= config.terrain_clearance_m) break;
    }
  }
  // Duration from the length of the control polygon (an upper bound of the curve length).
  double length = 0.0;
  for (int i = 0; i < 3; ++i) length += (s.points_[static_cast<std::size_t>(i + 1)] - s.points_[static_cast<std::size_t>(i)]).norm();
  s.duration_s_ = std::max(config.min_duration_s, length / config.speed_mps);
  return s;
}

double SwingTrajectory::Phase(double t) const { return std::clamp(t / duration_s_, 0.0, 1.0); }

Eigen::Vector3d SwingTrajectory::Bezier(double u) const {
  const double v = 1.0 - u;
  return v * v * v * points_[0] + 3.0 * v * v * u * points_[1] + 3.0 * v * u * u * points_[2] + u * u * u * points_[3];
}

Eigen::Vector3d SwingTrajectory::BezierDerivative(double u) const {
  const double v = 1.0 - u;
  return 3.0 * v * v * (points_[1] - points_[0]) + 6.0 * v * u * (points_[2] - points_[1]) +
         3.0 * u * u * (points_[3] - points_[2]);
}

Eigen::Vector3d SwingTrajectory::Position(double t) const { return Bezier(SmoothStep(Phase(t))); }

Eigen::Vector3d SwingTrajectory::Velocity(double t) const {
  if (t <= 0.0 || t >= duration_s_) return Eigen::Vector3d::Zero();
  const double u = Phase(t);
  return BezierDerivative(SmoothStep(u)) * SmoothStepRate(u) / duration_s_;
}

}  // namespace rbcp
