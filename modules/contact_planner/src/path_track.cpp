#include "path_track.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rbcp/core/error.h"

namespace rbcp::contact_planner_detail {

double WrapPi(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a < 0.0) a += 2.0 * M_PI;
  return a - M_PI;
}

Eigen::Matrix3d Yaw(double yaw) { return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

PathTrack::PathTrack(std::vector<RootPathSample> samples, double yaw_window) : s_(std::move(samples)) {
  RBCP_CHECK(!s_.empty(), "a path track needs a sample");
  for (std::size_t i = 1; i < s_.size(); ++i) {
    RBCP_CHECK(s_[i].t > s_[i - 1].t, "path times increase (sample " + std::to_string(i) + ")");
  }
  if (yaw_window <= 0.0 || s_.size() < 3) return;
  const std::size_t n = s_.size();
  // Prefix sums of the heading's unit vector.
  std::vector<Eigen::Vector2d> sum(n + 1, Eigen::Vector2d::Zero());
  for (std::size_t i = 0; i < n; ++i) sum[i + 1] = sum[i] + Eigen::Vector2d(std::cos(s_[i].yaw), std::sin(s_[i].yaw));
  std::vector<double> smoothed(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double w = std::min({yaw_window, s_[i].t - s_.front().t, s_.back().t - s_[i].t});
    const auto lo = std::lower_bound(s_.begin(), s_.end(), s_[i].t - w - 1e-12,
                                     [](const RootPathSample& s, double v) { return s.t < v; });
    const auto hi = std::upper_bound(s_.begin(), s_.end(), s_[i].t + w + 1e-12,
                                     [](double v, const RootPathSample& s) { return v < s.t; });
    const Eigen::Vector2d m = sum[static_cast<std::size_t>(hi - s_.begin())] - sum[static_cast<std::size_t>(lo - s_.begin())];
    smoothed[i] = m.norm() > 1e-9 ? std::atan2(m.y(), m.x()) : s_[i].yaw;
  }
  for (std::size_t i = 0; i < n; ++i) s_[i].yaw = smoothed[i];
}

PathPose PathTrack::At(double t) const {
  if (t <= s_.front().t) return {s_.front().p, s_.front().yaw};
  if (t >= s_.back().t) return {s_.back().p, s_.back().yaw};
  auto it = std::upper_bound(s_.begin(), s_.end(), t, [](double v, const RootPathSample& s) { return v < s.t; });
  const RootPathSample& b = *it;
  const RootPathSample& a = *(it - 1);
  const double dt = b.t - a.t;
  const double w = dt > 0.0 ? (t - a.t) / dt : 1.0;
  return {a.p + w * (b.p - a.p), WrapPi(a.yaw + w * WrapPi(b.yaw - a.yaw))};
}

Eigen::Isometry3d PathBasePose(const PathPose& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Yaw(pose.yaw);
  T.translation() = pose.p;
  return T;
}

PathPose LeadPose(const PathTrack& path, double t, double lead, double max_lead_yaw) {
  const PathPose now = path.At(t);
  PathPose ahead = path.At(t + lead);
  if (std::abs(WrapPi(ahead.yaw - now.yaw)) <= max_lead_yaw) return ahead;
  double lo = 0.0, hi = lead;
  for (int i = 0; i < 20; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (std::abs(WrapPi(path.At(t + mid).yaw - now.yaw)) <= max_lead_yaw) lo = mid;
    else hi = mid;
  }
  return path.At(t + lo);
}

}  // namespace rbcp::contact_planner_detail
