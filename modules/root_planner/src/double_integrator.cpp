#include "rbcp/root_planner/double_integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

constexpr double kVelocityTolerance = 1e-9;  // [m/s]
constexpr int kBisectionSteps = 100;

double Sign(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

// Displacement of the profile "ramp v0 -> vc at full acceleration, coast at vc, ramp vc -> v1 at
// full acceleration" of total duration T. Its derivative in vc is the coast time, so it is
// non-decreasing in vc wherever the coast time is non-negative.
double Displacement(double vc, double v0, double v1, double T, double a_max) {
  return vc * T + ((v0 - vc) * std::abs(v0 - vc) + (v1 - vc) * std::abs(v1 - vc)) / (2.0 * a_max);
}

// The coast velocities admissible in a duration T: [lowest, highest].
std::pair<double, double> CoastVelocityRange(double v0, double v1, double T, const AxisLimits& limits) {
  const double half = 0.5 * limits.a_max * T;
  const double mid = 0.5 * (v0 + v1);
  double lo = std::max(-limits.v_max, mid - half);
  double hi = std::min(limits.v_max, mid + half);
  // At T = |v1 - v0| / a_max the range collapses to one velocity; rounding may cross it.
  if (lo > hi) lo = hi = std::clamp(mid, -limits.v_max, limits.v_max);
  return {lo, hi};
}

double LowestDisplacement(double v0, double v1, double T, const AxisLimits& limits) {
  return Displacement(CoastVelocityRange(v0, v1, T, limits).first, v0, v1, T, limits.a_max);
}

void CheckMovingAxis(double v0, double v1, const AxisLimits& limits) {
  RBCP_CHECK(limits.v_max > 0.0 && limits.a_max > 0.0, "axis limits must be positive for a moving axis");
  RBCP_CHECK(std::abs(v0) <= limits.v_max + kVelocityTolerance && std::abs(v1) <= limits.v_max + kVelocityTolerance,
             "end velocities beyond v_max");
}

// Tolerance on a displacement [m] comparable to the rounding of the closed forms.
double DisplacementTolerance(double dp, double T, const AxisLimits& limits) {
  return 1e-12 * (1.0 + std::abs(dp) + limits.v_max * T);
}

// The profile with the switching times (t1, tc, t2) that goes from (p0, v0) to (p1, v1), if its
// accelerations and coast velocity are within the limits. Axes sharing switching times move in
// step: from rest to rest they follow a straight line.
std::optional<AxisProfile> PhaseProfile(double p0, double v0, double p1, double v1, double t1, double tc, double t2,
                                        const AxisLimits& limits) {
  if (!(t1 > 1e-9 && t2 > 1e-9)) return std::nullopt;
  const double dp = p1 - p0;
  const double a1 = (dp - v0 * (t1 + tc) - 0.5 * (v0 + v1) * t2) / (t1 * (0.5 * t1 + tc + 0.5 * t2));
  const double vc = v0 + a1 * t1;
  const double a2 = (v1 - vc) / t2;
  const double slack = 1e-9;
  if (std::abs(a1) > limits.a_max + slack || std::abs(a2) > limits.a_max + slack || std::abs(vc) > limits.v_max + slack) {
    return std::nullopt;
  }
  AxisProfile profile;
  profile.p0 = p0;
  profile.v0 = v0;
  profile.a1 = std::clamp(a1, -limits.a_max, limits.a_max);
  profile.t1 = t1;
  profile.tc = tc;
  profile.a2 = std::clamp(a2, -limits.a_max, limits.a_max);
  profile.t2 = t2;
  return profile;
}

}  // namespace

AxisState AxisProfile::Evaluate(double t) const {
  t = std::clamp(t, 0.0, Duration());
  const double d1 = std::min(t, t1);
  const double dc = std::clamp(t - t1, 0.0, tc);
  const double d2 = std::clamp(t - t1 - tc, 0.0, t2);
  const double v_coast = v0 + a1 * t1;
  AxisState s;
  s.p = p0 + v0 * d1 + 0.5 * a1 * d1 * d1 + v_coast * (dc + d2) + 0.5 * a2 * d2 * d2;
  s.v = (t < t1 ? v0 + a1 * d1 : v_coast + a2 * d2);
  if (t < t1) {
    s.a = a1;
  } else if (t < t1 + tc) {
    s.a = 0.0;
  } else if (t < t1 + tc + t2) {
    s.a = a2;
  }
  return s;
}

AxisProfile AxisProfile::Rest(double p, double duration) {
  AxisProfile profile;
  profile.p0 = p;
  profile.tc = std::max(0.0, duration);
  return profile;
}

double MinimumTime(double p0, double v0, double p1, double v1, const AxisLimits& limits) {
  CheckMovingAxis(v0, v1, limits);
  v0 = std::clamp(v0, -limits.v_max, limits.v_max);
  v1 = std::clamp(v1, -limits.v_max, limits.v_max);
  const double am = limits.a_max;
  const double vm = limits.v_max;
  const double dp = p1 - p0;
  const double t_direct = std::abs(v1 - v0) / am;
  const double d_direct = 0.5 * (v0 + v1) * t_direct;
  if (std::abs(dp - d_direct) <= DisplacementTolerance(dp, t_direct, limits)) return t_direct;
  // sigma: sign of the first ramp's acceleration.
  const double sigma = Sign(dp - d_direct);
  const double peak_sq = sigma * am * dp + 0.5 * (v0 * v0 + v1 * v1);
  const double vp = sigma * std::sqrt(std::max(0.0, peak_sq));
  if (std::abs(vp) <= vm) {
    return std::max(0.0, sigma * (vp - v0) / am) + std::max(0.0, sigma * (vp - v1) / am);
  }
  const double vc = sigma * vm;
  const double t1 = std::max(0.0, (vm - sigma * v0) / am);
  const double t2 = std::max(0.0, (vm - sigma * v1) / am);
  const double d_ramps = 0.5 * (v0 + vc) * t1 + 0.5 * (vc + v1) * t2;
  const double tc = std::max(0.0, (dp - d_ramps) / vc);
  return t1 + tc + t2;
}

std::pair<double, double> ReachableDisplacements(double v0, double v1, double duration, const AxisLimits& limits) {
  CheckMovingAxis(v0, v1, limits);
  const auto [lo, hi] = CoastVelocityRange(v0, v1, duration, limits);
  return {Displacement(lo, v0, v1, duration, limits.a_max), Displacement(hi, v0, v1, duration, limits.a_max)};
}

std::optional<TimeInterval> InfeasibleInterval(double p0, double v0, double p1, double v1, const AxisLimits& limits) {
  CheckMovingAxis(v0, v1, limits);
  double dp = p1 - p0;
  // Mirror so that both velocities are positive; with opposite signs (or a zero) there is none.
  if (v0 < 0.0 && v1 < 0.0) {
    v0 = -v0;
    v1 = -v1;
    dp = -dp;
  } else if (!(v0 > 0.0 && v1 > 0.0)) {
    return std::nullopt;
  }
  v0 = std::min(v0, limits.v_max);
  v1 = std::min(v1, limits.v_max);
  const double am = limits.a_max;
  // The lowest reachable displacement rises until the coast velocity can reach zero, at
  // T* = (v0 + v1) / a_max, where it peaks at (v0^2 + v1^2) / (2 a_max); then it falls without
  // bound. Durations where it exceeds dp are infeasible.
  const double t0 = std::abs(v1 - v0) / am;
  const double t_peak = (v0 + v1) / am;
  const double d_direct = 0.5 * (v0 + v1) * t0;
  const double d_peak = (v0 * v0 + v1 * v1) / (2.0 * am);
  const double tol = DisplacementTolerance(dp, t_peak, limits);
  if (dp < d_direct - tol || dp >= d_peak - tol) return std::nullopt;
  // Rising branch: D_min(t0) = d_direct <= dp < D_min(t_peak).
  double lo = t0;
  double hi = t_peak;
  for (int i = 0; i < kBisectionSteps && hi - lo > 1e-15 * (1.0 + hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (LowestDisplacement(v0, v1, mid, limits) <= dp ? lo : hi) = mid;
  }
  const double begin = lo;
  // Falling branch: find a duration where D_min <= dp again.
  double far = t_peak + 1.0;
  while (LowestDisplacement(v0, v1, far, limits) > dp) far = t_peak + 2.0 * (far - t_peak);
  lo = t_peak;
  hi = far;
  for (int i = 0; i < kBisectionSteps && hi - lo > 1e-15 * (1.0 + hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (LowestDisplacement(v0, v1, mid, limits) > dp ? lo : hi) = mid;
  }
  return TimeInterval{begin, hi};
}

std::optional<AxisProfile> FixedTimeProfile(double p0, double v0, double p1, double v1, double duration,
                                            const AxisLimits& limits) {
  CheckMovingAxis(v0, v1, limits);
  v0 = std::clamp(v0, -limits.v_max, limits.v_max);
  v1 = std::clamp(v1, -limits.v_max, limits.v_max);
  const double am = limits.a_max;
  const double dp = p1 - p0;
  const double t0 = std::abs(v1 - v0) / am;
  if (duration < t0 - 1e-12 * (1.0 + t0)) return std::nullopt;
  const double T = std::max(duration, t0);
  const auto [vlo, vhi] = CoastVelocityRange(v0, v1, T, limits);
  const double dlo = Displacement(vlo, v0, v1, T, am);
  const double dhi = Displacement(vhi, v0, v1, T, am);
  // The closed forms of MinimumTime and InfeasibleInterval land on the boundary up to rounding.
  const double tol = 1e-9 * (1.0 + std::abs(dp) + limits.v_max * T);
  if (dp < dlo - tol || dp > dhi + tol) return std::nullopt;
  double lo = vlo;
  double hi = vhi;
  if (dp <= dlo) {
    hi = vlo;
  } else if (dp >= dhi) {
    lo = vhi;
  } else {
    for (int i = 0; i < kBisectionSteps && hi - lo > 1e-16 * (1.0 + std::abs(hi)); ++i) {
      const double mid = 0.5 * (lo + hi);
      (Displacement(mid, v0, v1, T, am) < dp ? lo : hi) = mid;
    }
  }
  const double vc = 0.5 * (lo + hi);
  AxisProfile profile;
  profile.p0 = p0;
  profile.v0 = v0;
  profile.t1 = std::abs(vc - v0) / am;
  profile.a1 = Sign(vc - v0) * am;
  profile.t2 = std::abs(v1 - vc) / am;
  profile.a2 = Sign(v1 - vc) * am;
  profile.tc = std::max(0.0, T - profile.t1 - profile.t2);
  // Remove the ramp rounding so that the profile lasts exactly T.
  const double excess = profile.t1 + profile.tc + profile.t2 - T;
  if (excess > 0.0) {
    if (profile.t1 >= profile.t2) {
      profile.t1 = std::max(0.0, profile.t1 - excess);
    } else {
      profile.t2 = std::max(0.0, profile.t2 - excess);
    }
  }
  return profile;
}

PointSample DoubleIntegratorTrajectory::Sample(double t) const {
  t = std::clamp(t, 0.0, duration_);
  PointSample s;
  for (int i = 0; i < 3; ++i) {
    const AxisState a = axes_[static_cast<std::size_t>(i)].Evaluate(t);
    s.p[i] = a.p;
    s.v[i] = a.v;
    s.a[i] = a.a;
  }
  return s;
}

double MinimumTimeBound(const PointState& from, const PointState& to, const KinodynamicLimits& limits) {
  double bound = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (i == 2 && limits.VerticalFixed()) {
      if (std::abs(from.p.z() - to.p.z()) > 1e-9) return std::numeric_limits<double>::infinity();
      continue;
    }
    const AxisLimits& axis = limits.Axis(i);
    const double v0 = std::clamp(from.v[i], -axis.v_max, axis.v_max);
    const double v1 = std::clamp(to.v[i], -axis.v_max, axis.v_max);
    bound = std::max(bound, MinimumTime(from.p[i], v0, to.p[i], v1, axis));
  }
  return bound;
}

double SynchronisedDuration(const std::array<double, 3>& minimum_times,
                            const std::array<std::optional<TimeInterval>, 3>& infeasible, double duration_grid) {
  auto to_grid = [duration_grid](double t) {
    if (duration_grid <= 0.0) return t;
    // Multiples within rounding of t count as t itself.
    return std::ceil(t / duration_grid - 1e-9) * duration_grid;
  };
  double T = to_grid(*std::max_element(minimum_times.begin(), minimum_times.end()));
  // Each move goes to the end of an interval T lies in (or the next grid point after it); the
  // intervals are finite and T only grows, so the loop ends.
  for (int pass = 0; pass < 16; ++pass) {
    bool moved = false;
    for (const auto& interval : infeasible) {
      if (interval && T > interval->begin && T < interval->end) {
        T = to_grid(interval->end);
        moved = true;
      }
    }
    if (!moved) break;
  }
  return T;
}

std::optional<DoubleIntegratorTrajectory> Steer(const PointState& from, const PointState& to,
                                                const KinodynamicLimits& limits, double duration_grid) {
  const int moving_axes = limits.VerticalFixed() ? 2 : 3;
  if (limits.VerticalFixed()) {
    if (std::abs(from.p.z() - to.p.z()) > 1e-9 || std::abs(from.v.z()) > kVelocityTolerance ||
        std::abs(to.v.z()) > kVelocityTolerance) {
      return std::nullopt;
    }
  }
  std::array<double, 3> minimum_times{0.0, 0.0, 0.0};
  std::array<std::optional<TimeInterval>, 3> infeasible;
  for (int i = 0; i < moving_axes; ++i) {
    const AxisLimits& axis = limits.Axis(i);
    if (std::abs(from.v[i]) > axis.v_max + kVelocityTolerance || std::abs(to.v[i]) > axis.v_max + kVelocityTolerance) {
      return std::nullopt;
    }
    minimum_times[static_cast<std::size_t>(i)] = MinimumTime(from.p[i], from.v[i], to.p[i], to.v[i], axis);
    infeasible[static_cast<std::size_t>(i)] = InfeasibleInterval(from.p[i], from.v[i], to.p[i], to.v[i], axis);
  }
  double T = SynchronisedDuration(minimum_times, infeasible, duration_grid);
  std::array<AxisProfile, 3> axes;
  for (int attempt = 0; attempt < 3; ++attempt) {
    bool ok = true;
    for (int i = 0; i < moving_axes && ok; ++i) {
      auto profile = FixedTimeProfile(from.p[i], from.v[i], to.p[i], to.v[i], T, limits.Axis(i));
      if (profile) {
        axes[static_cast<std::size_t>(i)] = *profile;
      } else {
        ok = false;
      }
    }
    if (ok) {
      // Phase synchronisation: the other axes take the switching times of the axis that sets
      // the duration, when their bounds allow it.
      int lead = 0;
      for (int i = 1; i < moving_axes; ++i) {
        if (minimum_times[static_cast<std::size_t>(i)] > minimum_times[static_cast<std::size_t>(lead)]) lead = i;
      }
      const AxisProfile& lead_profile = axes[static_cast<std::size_t>(lead)];
      for (int i = 0; i < moving_axes; ++i) {
        if (i == lead) continue;
        auto phased = PhaseProfile(from.p[i], from.v[i], to.p[i], to.v[i], lead_profile.t1, lead_profile.tc,
                                   lead_profile.t2, limits.Axis(i));
        if (phased) axes[static_cast<std::size_t>(i)] = *phased;
      }
      if (moving_axes == 2) axes[2] = AxisProfile::Rest(from.p.z(), T);
      return DoubleIntegratorTrajectory(axes, T);
    }
    // A boundary of an infeasible interval missed by rounding: step just past it.
    T += duration_grid > 0.0 ? duration_grid : 1e-9 * (1.0 + T);
  }
  RBCP_CHECK(false, "no synchronised profile at the synchronised duration");
}

}  // namespace rbcp
