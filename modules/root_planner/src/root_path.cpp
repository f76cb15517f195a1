#include "rbcp/root_planner/root_path.h"

#include <algorithm>
#include <cmath>

#include "rbcp/core/angle.h"
#include "rbcp/core/error.h"

namespace rbcp {

double YawModel::Yaw(const Eigen::Vector2d& v_xy, double rest_yaw) const {
  const double speed = v_xy.norm();
  const double x = std::min(1.0, speed / blend_speed);
  const double w = x * x * (3.0 - 2.0 * x);
  Eigen::Vector2d u = (1.0 - w) * Eigen::Vector2d(std::cos(rest_yaw), std::sin(rest_yaw));
  if (speed > 0.0) u += (w / speed) * v_xy;
  // u vanishes only when moving straight against the rest yaw at exactly half blend.
  if (u.squaredNorm() < 1e-24) return WrapAngle(rest_yaw);
  return std::atan2(u.y(), u.x());
}

RootSegment RootSegment::Whole(const DoubleIntegratorTrajectory& trajectory, double rest_yaw_begin,
                               double rest_yaw_end) {
  RootSegment segment;
  segment.trajectory = trajectory;
  segment.begin = 0.0;
  segment.end = trajectory.Duration();
  segment.rest_yaw_begin = rest_yaw_begin;
  segment.rest_yaw_end = rest_yaw_end;
  return segment;
}

double RootSegment::RestYaw(double t) const {
  const double d = Duration();
  const double s = d > 0.0 ? std::clamp(t / d, 0.0, 1.0) : 1.0;
  return WrapAngle(rest_yaw_begin + s * WrapAngle(rest_yaw_end - rest_yaw_begin));
}

RootPathSample RootSegment::Sample(double t, const YawModel& yaw) const {
  t = std::clamp(t, 0.0, Duration());
  const PointSample x = trajectory.Sample(begin + t);
  RootPathSample s;
  s.t = t;
  s.p = x.p;
  s.v = x.v;
  s.a = x.a;
  s.rest_yaw = RestYaw(t);
  s.yaw = yaw.Yaw(x.v.head<2>(), s.rest_yaw);
  return s;
}

RootSegment RootSegment::Part(double from, double to) const {
  from = std::clamp(from, 0.0, Duration());
  to = std::clamp(to, from, Duration());
  RootSegment part = *this;
  part.begin = begin + from;
  part.end = begin + to;
  part.rest_yaw_begin = RestYaw(from);
  part.rest_yaw_end = RestYaw(to);
  return part;
}

void RootPath::Append(const RootSegment& segment) {
  RBCP_CHECK(segment.end >= segment.begin, "segment with negative duration");
  segments_.push_back(segment);
  ends_.push_back(Duration() + segment.Duration());
}

RootPathSample RootPath::Sample(double t) const {
  RBCP_CHECK(!segments_.empty(), "sampling an empty path");
  t = std::clamp(t, 0.0, Duration());
  const auto it = std::lower_bound(ends_.begin(), ends_.end(), t);
  const std::size_t i = it == ends_.end() ? ends_.size() - 1 : static_cast<std::size_t>(it - ends_.begin());
  const double start = i == 0 ? 0.0 : ends_[i - 1];
  RootPathSample s = segments_[i].Sample(t - start, yaw_);
  s.t = t;
  return s;
}

std::vector<RootPathSample> RootPath::SampleEvery(double dt) const {
  RBCP_CHECK(dt > 0.0, "sampling step must be positive");
  std::vector<RootPathSample> samples;
  const double T = Duration();
  const auto n = static_cast<long>(std::floor(T / dt + 1e-9));
  samples.reserve(static_cast<std::size_t>(n) + 2);
  for (long k = 0; k <= n; ++k) samples.push_back(Sample(std::min(T, static_cast<double>(k) * dt)));
  if (samples.back().t < T - 1e-12) samples.push_back(Sample(T));
  return samples;
}

RootPath RootPath::Part(double from, double to) const {
  RootPath part(yaw_);
  from = std::clamp(from, 0.0, Duration());
  to = std::clamp(to, from, Duration());
  double start = 0.0;
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    const double end = ends_[i];
    const double a = std::max(from, start);
    const double b = std::min(to, end);
    if (b > a) part.Append(segments_[i].Part(a - start, b - start));
    start = end;
  }
  return part;
}

}  // namespace rbcp
