#pragma once
/// A time-parametrised root (trunk) path: a chain of steered double-integrator pieces, plus the
/// heading model that turns velocity into yaw.
///
/// Yaw follows the horizontal velocity. At rest the trunk keeps a "rest yaw" (the start yaw on
/// the way out, the goal yaw on arrival, interpolated in between along a connecting piece), and
/// the heading is blended from the rest yaw to the velocity direction as the horizontal speed s
/// grows: the yaw is the direction of w(s) v/|v| + (1 - w(s)) (cos r, sin r), with
/// w = smoothstep(s / blend_speed). The yaw is therefore a continuous function of the state and
/// there is no jump at zero-velocity path ends.

#include <Eigen/Core>
#include <vector>

#include "rbcp/core/root_path_sample.h"
#include "rbcp/root_planner/double_integrator.h"

namespace rbcp {

/// Heading from velocity, blended with the rest yaw at low speed.
struct YawModel {
  double blend_speed = 0.1;  ///< [m/s] horizontal speed from which the yaw fully follows the velocity, > 0

  /// Yaw [rad] in (-pi, pi] for a horizontal velocity v_xy [m/s] and a rest yaw [rad].
  double Yaw(const Eigen::Vector2d& v_xy, double rest_yaw) const;
};

/// The part [begin, end] of a steered trajectory, with the rest yaw going linearly (the short
/// way round) from rest_yaw_begin to rest_yaw_end over that part.
struct RootSegment {
  DoubleIntegratorTrajectory trajectory;
  double begin = 0.0;  ///< [s] in trajectory time
  double end = 0.0;    ///< [s] in trajectory time, >= begin
  double rest_yaw_begin = 0.0;
  double rest_yaw_end = 0.0;

  /// A whole trajectory with one rest-yaw interpolation.
  static RootSegment Whole(const DoubleIntegratorTrajectory& trajectory, double rest_yaw_begin, double rest_yaw_end);

  double Duration() const { return end - begin; }
  /// The state at time t in [0, Duration()] from the segment start (clamped); `t` of the result
  /// is this local time.
  RootPathSample Sample(double t, const YawModel& yaw) const;
  double RestYaw(double t) const;
  /// The part [from, to] of this segment (local times, clamped, from <= to).
  RootSegment Part(double from, double to) const;
};

/// A chain of segments, each starting where the previous ends.
class RootPath {
 public:
  RootPath() = default;
  explicit RootPath(YawModel yaw) : yaw_(yaw) {}

  void Append(const RootSegment& segment);
  void Clear() {
    segments_.clear();
    ends_.clear();
  }
  bool Empty() const { return segments_.empty(); }
  const std::vector<RootSegment>& Segments() const { return segments_; }
  const YawModel& Yaw() const { return yaw_; }

  /// Total duration [s].
  double Duration() const { return ends_.empty() ? 0.0 : ends_.back(); }
  /// State at time t (clamped to [0, Duration()]).
  RootPathSample Sample(double t) const;
  /// Samples at 0, dt, 2 dt, ... and always the final state.
  std::vector<RootPathSample> SampleEvery(double dt) const;
  /// The path's part [from, to] as a new path (times shifted to start at 0); empty when
  /// from >= to.
  RootPath Part(double from, double to) const;

 private:
  YawModel yaw_;
  std::vector<RootSegment> segments_;
  std::vector<double> ends_;  ///< cumulative end time of each segment [s]
};

}  // namespace rbcp
