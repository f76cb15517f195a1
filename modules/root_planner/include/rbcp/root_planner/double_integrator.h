#pragma once
/// Time-optimal steering of a point mass with bounded velocity and acceleration (per axis), and
/// synchronisation of the three axes to one common duration.
///
/// One axis is a double integrator p'' = a with |v| <= v_max and |a| <= a_max. Every profile used
/// here has at most three phases: a ramp at constant acceleration, a coast at constant velocity,
/// a second ramp. The minimum-time profile is bang-bang or bang-coast-bang. For a longer, fixed
/// duration T the profile ramps at full acceleration to a coast velocity v_c, coasts, and ramps
/// at full acceleration to the final velocity; v_c is chosen so that the displacement is exact.
/// The displacements reachable in exactly T form an interval [D_min(T), D_max(T)]; when both end
/// velocities are non-zero with the same sign there can be one interval of durations in which the
/// axis cannot arrive exactly (it would have to stop and come back, which takes longer).

#include <Eigen/Core>
#include <array>
#include <optional>

namespace rbcp {

/// Bounds of one axis. a_max == 0 marks an axis that does not move.
struct AxisLimits {
  double v_max = 0.3;  ///< [m/s], > 0 for a moving axis
  double a_max = 1.0;  ///< [m/s^2], > 0 for a moving axis, 0 for a fixed axis
};

/// Position, velocity and acceleration of one axis at one time.
struct AxisState {
  double p = 0.0;  ///< [m]
  double v = 0.0;  ///< [m/s]
  double a = 0.0;  ///< [m/s^2]
};

/// A three-phase profile of one axis: from (p0, v0) accelerate at a1 for t1, coast for tc, then
/// accelerate at a2 for t2. Times [s], accelerations [m/s^2].
struct AxisProfile {
  double p0 = 0.0;
  double v0 = 0.0;
  double a1 = 0.0;
  double t1 = 0.0;
  double tc = 0.0;
  double a2 = 0.0;
  double t2 = 0.0;

  double Duration() const { return t1 + tc + t2; }
  /// State at time t; t is clamped to [0, Duration()] (the axis rests in its end state afterwards,
  /// with zero acceleration).
  AxisState Evaluate(double t) const;
  /// State at the end of the profile.
  AxisState End() const { return Evaluate(Duration()); }
  /// Profile that stays at p with zero velocity for `duration`.
  static AxisProfile Rest(double p, double duration);
};

/// Open interval of durations (begin, end) [s]; both ends are feasible.
struct TimeInterval {
  double begin = 0.0;
  double end = 0.0;
};

/// Minimum time [s] to go from (p0, v0) to (p1, v1) under the limits. Requires a moving axis and
/// |v0|, |v1| <= v_max (checked, up to 1e-9 m/s).
double MinimumTime(double p0, double v0, double p1, double v1, const AxisLimits& limits);

/// The durations T > MinimumTime() at which the axis cannot arrive exactly, if any.
std::optional<TimeInterval> InfeasibleInterval(double p0, double v0, double p1, double v1, const AxisLimits& limits);

/// The displacements [m] reachable in exactly `duration` from velocity v0 to v1: [first, second].
/// Requires duration >= |v1 - v0| / a_max.
std::pair<double, double> ReachableDisplacements(double v0, double v1, double duration, const AxisLimits& limits);

/// The profile that arrives at (p1, v1) at exactly `duration`, or nullopt when that duration is
/// infeasible (shorter than the minimum time or inside the infeasible interval).
std::optional<AxisProfile> FixedTimeProfile(double p0, double v0, double p1, double v1, double duration,
                                            const AxisLimits& limits);

/// Limits of the root's translation: the same bounds for x and y, separate ones for z.
struct KinodynamicLimits {
  AxisLimits horizontal;  ///< x and y
  AxisLimits vertical;    ///< z; a_max == 0 keeps z constant (the z of both states must match)
  bool VerticalFixed() const { return vertical.a_max <= 0.0; }
  const AxisLimits& Axis(int i) const { return i == 2 ? vertical : horizontal; }
};

/// Position and velocity of the root [m], [m/s], world frame.
struct PointState {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
};

/// Sample of a 3D trajectory.
struct PointSample {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  ///< [m/s]
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< [m/s^2]
};

/// Three axis profiles of one common duration.
class DoubleIntegratorTrajectory {
 public:
  DoubleIntegratorTrajectory() = default;
  DoubleIntegratorTrajectory(const std::array<AxisProfile, 3>& axes, double duration)
      : axes_(axes), duration_(duration) {}

  double Duration() const { return duration_; }
  /// State at time t, clamped to [0, Duration()].
  PointSample Sample(double t) const;
  const AxisProfile& Axis(int i) const { return axes_[static_cast<std::size_t>(i)]; }

 private:
  std::array<AxisProfile, 3> axes_{};
  double duration_ = 0.0;
};

/// Lower bound of the steering duration [s]: the largest per-axis minimum time. Infinite when a
/// fixed vertical axis would have to move. Used as the (asymmetric) distance between states.
double MinimumTimeBound(const PointState& from, const PointState& to, const KinodynamicLimits& limits);

/// The smallest duration >= every axis' minimum time that lies outside every axis' infeasible
/// interval, given per-axis minimum times and intervals; with `duration_grid` > 0 the smallest
/// such multiple of duration_grid.
double SynchronisedDuration(const std::array<double, 3>& minimum_times,
                            const std::array<std::optional<TimeInterval>, 3>& infeasible, double duration_grid = 0.0);

/// Time-optimal synchronised steering from `from` to `to`: every axis arrives at the same time,
/// the smallest one all can meet. Axes are phase-synchronised where their bounds allow: they
/// switch acceleration at the times of the axis with the longest minimum time (so a motion from
/// rest to rest is a straight line); the others use FixedTimeProfile. With `duration_grid` > 0 [s] the duration is the smallest
/// feasible multiple of it instead (so that pieces of a path line up with a sampling grid).
/// nullopt when a velocity is beyond its bound (by more than 1e-9 m/s) or a fixed vertical axis
/// would have to move or has a non-zero velocity.
std::optional<DoubleIntegratorTrajectory> Steer(const PointState& from, const PointState& to,
                                                const KinodynamicLimits& limits, double duration_grid = 0.0);

}  // namespace rbcp
