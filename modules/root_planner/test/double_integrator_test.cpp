#include "rbcp/root_planner/double_integrator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rbcp {
namespace {

constexpr double kTol = 1e-7;

// Checks that the profile starts and ends at the given states, lasts `duration` and respects the
// limits on a fine time grid (and in between, velocity is piecewise linear so the grid suffices).
void ExpectProfileConnects(const AxisProfile& profile, double p0, double v0, double p1, double v1, double duration,
                           const AxisLimits& limits) {
  EXPECT_NEAR(profile.Duration(), duration, 1e-9);
  const AxisState start = profile.Evaluate(0.0);
  EXPECT_NEAR(start.p, p0, kTol);
  EXPECT_NEAR(start.v, v0, kTol);
  const AxisState end = profile.Evaluate(duration);
  EXPECT_NEAR(end.p, p1, kTol);
  EXPECT_NEAR(end.v, v1, kTol);
  EXPECT_LE(std::abs(profile.a1), limits.a_max + 1e-12);
  EXPECT_LE(std::abs(profile.a2), limits.a_max + 1e-12);
  EXPECT_GE(profile.t1, 0.0);
  EXPECT_GE(profile.tc, 0.0);
  EXPECT_GE(profile.t2, 0.0);
  const int n = 200;
  for (int k = 0; k <= n; ++k) {
    const AxisState s = profile.Evaluate(duration * k / n);
    EXPECT_LE(std::abs(s.v), limits.v_max + 1e-9);
    EXPECT_LE(std::abs(s.a), limits.a_max + 1e-12);
  }
}

TEST(AxisProfileTest, EvaluateIntegratesThePhases) {
  AxisProfile profile;
  profile.p0 = 1.0;
  profile.v0 = 0.5;
  profile.a1 = -1.0;
  profile.t1 = 0.5;
  profile.tc = 1.0;
  profile.a2 = 2.0;
  profile.t2 = 0.25;
  // End of first ramp: v = 0, p = 1 + 0.25 - 0.125.
  EXPECT_NEAR(profile.Evaluate(0.5).p, 1.125, 1e-12);
  EXPECT_NEAR(profile.Evaluate(0.5).v, 0.0, 1e-12);
  EXPECT_EQ(profile.Evaluate(0.25).a, -1.0);
  EXPECT_EQ(profile.Evaluate(1.0).a, 0.0);
  EXPECT_EQ(profile.Evaluate(1.6).a, 2.0);
  // Second ramp: v 0 -> 0.5 over 0.25 s covers 0.0625 m.
  EXPECT_NEAR(profile.End().p, 1.1875, 1e-12);
  EXPECT_NEAR(profile.End().v, 0.5, 1e-12);
  EXPECT_EQ(profile.End().a, 0.0);
  // Clamped beyond the end.
  EXPECT_NEAR(profile.Evaluate(10.0).p, 1.1875, 1e-12);
}

TEST(MinimumTimeTest, RestToRestClosedForms) {
  const AxisLimits limits{0.3, 1.0};
  // Bang-bang: 0.05 m needs a peak of sqrt(0.05) < 0.3, T = 2 sqrt(0.05).
  EXPECT_NEAR(MinimumTime(0.0, 0.0, 0.05, 0.0, limits), 2.0 * std::sqrt(0.05), 1e-12);
  // Bang-coast-bang: 1.5 m: ramps of 0.3 s cover 0.09 m, coast 1.41 m / 0.3 m/s = 4.7 s.
  EXPECT_NEAR(MinimumTime(0.0, 0.0, 1.5, 0.0, limits), 0.6 + 4.7, 1e-12);
  EXPECT_NEAR(MinimumTime(2.0, 0.0, 0.5, 0.0, limits), 0.6 + 4.7, 1e-12);
  EXPECT_EQ(MinimumTime(1.0, 0.0, 1.0, 0.0, limits), 0.0);
  // Pure velocity change: 0 -> 0.3 over 0.045 m takes 0.3 s.
  EXPECT_NEAR(MinimumTime(0.0, 0.0, 0.045, 0.3, limits), 0.3, 1e-12);
}

TEST(MinimumTimeTest, IsTheFirstFeasibleDuration) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-2.0, 2.0);
  const AxisLimits limits{0.3, 1.0};
  std::uniform_real_distribution<double> vel(-limits.v_max, limits.v_max);
  for (int k = 0; k < 2000; ++k) {
    const double p0 = pos(rng), p1 = pos(rng), v0 = vel(rng), v1 = vel(rng);
    const double t_min = MinimumTime(p0, v0, p1, v1, limits);
    auto at_min = FixedTimeProfile(p0, v0, p1, v1, t_min, limits);
    ASSERT_TRUE(at_min.has_value()) << p0 << " " << v0 << " " << p1 << " " << v1;
    ExpectProfileConnects(*at_min, p0, v0, p1, v1, t_min, limits);
    // Slightly shorter cannot work.
    const double shorter = t_min * (1.0 - 1e-4) - 1e-6;
    if (shorter > 0.0) {
      EXPECT_FALSE(FixedTimeProfile(p0, v0, p1, v1, shorter, limits).has_value())
          << p0 << " " << v0 << " " << p1 << " " << v1 << " t_min " << t_min;
    }
  }
}

TEST(InfeasibleIntervalTest, MovingThroughAShortDistanceCannotTakeLong) {
  // Moving at 1 m/s in and out over 0.1 m: coasting takes 0.1 s; taking longer means braking,
  // which covers more ground than 0.1 m until the axis can stop, back up and come again.
  const AxisLimits limits{1.0, 1.0};
  const double p1 = 0.1;
  EXPECT_NEAR(MinimumTime(0.0, 1.0, p1, 1.0, limits), 0.1, 1e-12);
  auto interval = InfeasibleInterval(0.0, 1.0, p1, 1.0, limits);
  ASSERT_TRUE(interval.has_value());
  // D_min(T) = T - T^2 / 4 on the rising branch: equals 0.1 at T = 2 - sqrt(3.6).
  EXPECT_NEAR(interval->begin, 2.0 - std::sqrt(3.6), 1e-9);
  EXPECT_GT(interval->end, 2.0);
  for (double T : {0.2, 1.0, 2.0, 3.0, interval->end - 1e-3}) {
    if (T > interval->begin && T < interval->end) {
      EXPECT_FALSE(FixedTimeProfile(0.0, 1.0, p1, 1.0, T, limits).has_value()) << T;
    }
  }
  for (double T : {interval->begin, interval->end, interval->end + 0.5, 10.0}) {
    auto profile = FixedTimeProfile(0.0, 1.0, p1, 1.0, T, limits);
    ASSERT_TRUE(profile.has_value()) << T;
    ExpectProfileConnects(*profile, 0.0, 1.0, p1, 1.0, T, limits);
  }
  // The mirrored problem has the mirrored interval; opposite velocities have none.
  auto mirrored = InfeasibleInterval(0.0, -1.0, -p1, -1.0, limits);
  ASSERT_TRUE(mirrored.has_value());
  EXPECT_NEAR(mirrored->begin, interval->begin, 1e-12);
  EXPECT_NEAR(mirrored->end, interval->end, 1e-12);
  EXPECT_FALSE(InfeasibleInterval(0.0, 1.0, p1, -1.0, limits).has_value());
  EXPECT_FALSE(InfeasibleInterval(0.0, 0.0, p1, 1.0, limits).has_value());
}

TEST(InfeasibleIntervalTest, MatchesTheReachableDisplacements) {
  // Random same-sign cases: inside the interval the displacement is out of [D_min, D_max];
  // outside (beyond the minimum time) it is within.
  std::mt19937_64 rng(11);
  const AxisLimits limits{0.3, 1.0};
  std::uniform_real_distribution<double> vel(0.01, limits.v_max);
  std::uniform_real_distribution<double> pos(-0.02, 0.1);
  int intervals = 0;
  for (int k = 0; k < 2000; ++k) {
    const double v0 = vel(rng), v1 = vel(rng), dp = pos(rng);
    const double t_min = MinimumTime(0.0, v0, dp, v1, limits);
    auto interval = InfeasibleInterval(0.0, v0, dp, v1, limits);
    if (interval) {
      ++intervals;
      EXPECT_GE(interval->begin, t_min - 1e-9);
      EXPECT_GT(interval->end, interval->begin);
      const double mid = 0.5 * (interval->begin + interval->end);
      const auto [lo, hi] = ReachableDisplacements(v0, v1, mid, limits);
      EXPECT_TRUE(dp < lo || dp > hi);
      EXPECT_FALSE(FixedTimeProfile(0.0, v0, dp, v1, mid, limits).has_value());
    }
    for (double extra : {0.0, 0.05, 0.5, 2.0, 8.0}) {
      const double T = t_min + extra;
      const bool inside = interval && T > interval->begin + 1e-9 && T < interval->end - 1e-9;
      auto profile = FixedTimeProfile(0.0, v0, dp, v1, T, limits);
      if (inside) {
        EXPECT_FALSE(profile.has_value());
      } else if (!(interval && (std::abs(T - interval->begin) < 1e-9 || std::abs(T - interval->end) < 1e-9))) {
        ASSERT_TRUE(profile.has_value()) << v0 << " " << v1 << " " << dp << " T " << T;
        ExpectProfileConnects(*profile, 0.0, v0, dp, v1, T, limits);
      }
    }
  }
  EXPECT_GT(intervals, 200);
}

TEST(SynchronisedDurationTest, SkipsInfeasibleIntervals) {
  std::array<std::optional<TimeInterval>, 3> none{};
  EXPECT_EQ(SynchronisedDuration({1.0, 2.0, 0.5}, none), 2.0);
  std::array<std::optional<TimeInterval>, 3> intervals{};
  intervals[0] = TimeInterval{1.5, 3.0};
  EXPECT_EQ(SynchronisedDuration({1.0, 2.0, 0.5}, intervals), 3.0);
  // Moving out of one interval can land in another.
  intervals[1] = TimeInterval{2.5, 4.0};
  EXPECT_EQ(SynchronisedDuration({1.0, 2.0, 0.5}, intervals), 4.0);
  // The ends are feasible.
  std::array<std::optional<TimeInterval>, 3> at_end{};
  at_end[2] = TimeInterval{1.0, 2.0};
  EXPECT_EQ(SynchronisedDuration({1.0, 2.0, 0.5}, at_end), 2.0);
}

TEST(SteerTest, ReachesTheTargetStateAtTheComputedTimeWithinBounds) {
  std::mt19937_64 rng(3);
  KinodynamicLimits limits;
  limits.horizontal = {0.3, 1.0};
  limits.vertical = {0.3, 5.0};
  std::uniform_real_distribution<double> pos(-3.0, 3.0);
  std::uniform_real_distribution<double> height(0.4, 1.0);
  std::uniform_real_distribution<double> vel(-0.3, 0.3);
  std::bernoulli_distribution rest(0.3);
  for (int k = 0; k < 2000; ++k) {
    PointState from, to;
    from.p = {pos(rng), pos(rng), height(rng)};
    to.p = {pos(rng), pos(rng), height(rng)};
    if (!rest(rng)) from.v = {vel(rng), vel(rng), vel(rng)};
    if (!rest(rng)) to.v = {vel(rng), vel(rng), vel(rng)};
    auto trajectory = Steer(from, to, limits);
    ASSERT_TRUE(trajectory.has_value());
    const double T = trajectory->Duration();
    EXPECT_GE(T, MinimumTimeBound(from, to, limits) - 1e-12);
    const PointSample start = trajectory->Sample(0.0);
    const PointSample end = trajectory->Sample(T);
    EXPECT_TRUE(start.p.isApprox(from.p, 1e-9) && (start.v - from.v).norm() < 1e-9);
    EXPECT_LT((end.p - to.p).norm(), 1e-7) << k;
    EXPECT_LT((end.v - to.v).norm(), 1e-7) << k;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(trajectory->Axis(i).Duration(), T, 1e-9);
    for (int s = 0; s <= 100; ++s) {
      const PointSample x = trajectory->Sample(T * s / 100.0);
      for (int i = 0; i < 3; ++i) {
        EXPECT_LE(std::abs(x.v[i]), limits.Axis(i).v_max + 1e-9);
        EXPECT_LE(std::abs(x.a[i]), limits.Axis(i).a_max + 1e-12);
      }
    }
    // No shorter common duration exists: every axis can meet T, and T is the smallest duration
    // above the largest minimum time that no axis' infeasible interval contains.
    std::array<double, 3> t_min{};
    std::array<std::optional<TimeInterval>, 3> gaps{};
    for (int i = 0; i < 3; ++i) {
      t_min[static_cast<std::size_t>(i)] = MinimumTime(from.p[i], from.v[i], to.p[i], to.v[i], limits.Axis(i));
      gaps[static_cast<std::size_t>(i)] = InfeasibleInterval(from.p[i], from.v[i], to.p[i], to.v[i], limits.Axis(i));
    }
    EXPECT_NEAR(T, SynchronisedDuration(t_min, gaps), 1e-6);
  }
}

TEST(SteerTest, RestToRestIsAStraightLine) {
  KinodynamicLimits limits;
  limits.horizontal = {0.3, 1.0};
  limits.vertical = {0.3, 5.0};
  PointState from, to;
  from.p = {-1.0, 0.2, 0.45};
  to.p = {0.5, -0.4, 0.97};
  auto trajectory = Steer(from, to, limits);
  ASSERT_TRUE(trajectory.has_value());
  const Eigen::Vector3d d = (to.p - from.p).normalized();
  for (int s = 0; s <= 50; ++s) {
    const Eigen::Vector3d p = trajectory->Sample(trajectory->Duration() * s / 50.0).p - from.p;
    EXPECT_LT((p - p.dot(d) * d).norm(), 1e-9);
  }
  EXPECT_NEAR(trajectory->Duration(), MinimumTime(-1.0, 0.0, 0.5, 0.0, limits.horizontal), 1e-12);
}

TEST(SteerTest, FixedVerticalAxisStaysPut) {
  KinodynamicLimits limits;
  limits.horizontal = {0.3, 1.0};
  limits.vertical = {0.0, 0.0};
  PointState from, to;
  from.p = {0.0, 0.0, 0.45};
  to.p = {1.0, -0.5, 0.45};
  to.v = {0.1, 0.0, 0.0};
  auto trajectory = Steer(from, to, limits);
  ASSERT_TRUE(trajectory.has_value());
  for (int s = 0; s <= 10; ++s) {
    const PointSample x = trajectory->Sample(trajectory->Duration() * s / 10.0);
    EXPECT_EQ(x.p.z(), 0.45);
    EXPECT_EQ(x.v.z(), 0.0);
  }
  to.p.z() = 0.5;
  EXPECT_FALSE(Steer(from, to, limits).has_value());
  EXPECT_EQ(MinimumTimeBound(from, to, limits), std::numeric_limits<double>::infinity());
}

TEST(SteerTest, RejectsVelocitiesBeyondTheBound) {
  KinodynamicLimits limits;
  limits.horizontal = {0.3, 1.0};
  limits.vertical = {0.3, 5.0};
  PointState from, to;
  to.p = {1.0, 0.0, 0.0};
  from.v = {0.31, 0.0, 0.0};
  EXPECT_FALSE(Steer(from, to, limits).has_value());
}

TEST(SteerTest, SameStateGivesAnEmptyTrajectory) {
  KinodynamicLimits limits;
  PointState s;
  s.p = {1.0, 2.0, 0.5};
  auto trajectory = Steer(s, s, limits);
  ASSERT_TRUE(trajectory.has_value());
  EXPECT_EQ(trajectory->Duration(), 0.0);
  EXPECT_TRUE(trajectory->Sample(0.0).p.isApprox(s.p));
}

}  // namespace
}  // namespace rbcp

namespace rbcp {
namespace {

TEST(SteerTest, DurationGridGivesMultiplesThatStillReachTheTarget) {
  std::mt19937_64 rng(5);
  KinodynamicLimits limits;
  limits.horizontal = {0.3, 1.0};
  limits.vertical = {0.3, 5.0};
  std::uniform_real_distribution<double> pos(-2.0, 2.0);
  std::uniform_real_distribution<double> vel(-0.3, 0.3);
  const double grid = 0.05;
  for (int k = 0; k < 1000; ++k) {
    PointState from, to;
    from.p = {pos(rng), pos(rng), 0.5 + 0.1 * pos(rng)};
    to.p = {pos(rng), pos(rng), 0.5 + 0.1 * pos(rng)};
    from.v = {vel(rng), vel(rng), vel(rng)};
    to.v = {vel(rng), vel(rng), vel(rng)};
    auto free = Steer(from, to, limits);
    auto gridded = Steer(from, to, limits, grid);
    ASSERT_TRUE(free && gridded);
    const double T = gridded->Duration();
    EXPECT_NEAR(T / grid, std::round(T / grid), 1e-9);
    EXPECT_GE(T, free->Duration() - 1e-9);
    const PointSample end = gridded->Sample(T);
    EXPECT_LT((end.p - to.p).norm(), 1e-7);
    EXPECT_LT((end.v - to.v).norm(), 1e-7);
  }
}

}  // namespace
}  // namespace rbcp
