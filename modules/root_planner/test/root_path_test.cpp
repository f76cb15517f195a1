#include "rbcp/root_planner/root_path.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rbcp/core/angle.h"

namespace rbcp {
namespace {

TEST(YawModelTest, RestYawAtRestHeadingAtSpeed) {
  const YawModel model{0.1};
  EXPECT_NEAR(model.Yaw({0.0, 0.0}, 0.7), 0.7, 1e-15);
  EXPECT_NEAR(model.Yaw({0.0, 0.2}, 0.7), M_PI / 2.0, 1e-12);
  EXPECT_NEAR(model.Yaw({-0.1, 0.0}, 0.0), M_PI, 1e-12);
  // Half way through the blend, sideways motion: the blended direction bisects.
  const double half = model.Yaw({0.0, 0.05}, 0.0);
  EXPECT_NEAR(half, M_PI / 4.0, 1e-12);
}

TEST(YawModelTest, ContinuousWhenStartingFromRest) {
  // Speeding up from rest along a direction 120 deg from the rest yaw: the yaw turns smoothly.
  const YawModel model{0.1};
  const Eigen::Vector2d dir(std::cos(2.0 * M_PI / 3.0), std::sin(2.0 * M_PI / 3.0));
  double previous = model.Yaw({0.0, 0.0}, 0.0);
  for (int k = 1; k <= 1000; ++k) {
    const double yaw = model.Yaw(dir * (0.15 * k / 1000.0), 0.0);
    EXPECT_LT(std::abs(WrapAngle(yaw - previous)), 0.02) << k;
    previous = yaw;
  }
  EXPECT_NEAR(previous, 2.0 * M_PI / 3.0, 1e-12);
}

DoubleIntegratorTrajectory Line(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  KinodynamicLimits limits;
  limits.horizontal = {0.3, 1.0};
  limits.vertical = {0.3, 5.0};
  PointState a, b;
  a.p = from;
  b.p = to;
  return *Steer(a, b, limits, 0.05);
}

TEST(RootPathTest, ChainsSegmentsAndSamplesOnAGrid) {
  RootPath path(YawModel{0.1});
  const auto first = Line({0, 0, 0.45}, {1, 0, 0.45});
  const auto second = Line({1, 0, 0.45}, {1, 1, 0.45});
  path.Append(RootSegment::Whole(first, 0.0, 0.0));
  path.Append(RootSegment::Whole(second, 0.0, M_PI / 2.0));
  EXPECT_NEAR(path.Duration(), first.Duration() + second.Duration(), 1e-12);
  EXPECT_TRUE(path.Sample(0.0).p.isApprox(Eigen::Vector3d(0, 0, 0.45)));
  EXPECT_TRUE(path.Sample(first.Duration()).p.isApprox(Eigen::Vector3d(1, 0, 0.45)));
  EXPECT_LT((path.Sample(path.Duration()).p - Eigen::Vector3d(1, 1, 0.45)).norm(), 1e-9);
  // Yaw: start yaw at rest, heading +x while moving along x, the goal yaw at the end.
  EXPECT_NEAR(path.Sample(0.0).yaw, 0.0, 1e-12);
  EXPECT_NEAR(path.Sample(0.5 * first.Duration()).yaw, 0.0, 1e-9);
  EXPECT_NEAR(path.Sample(first.Duration() + 0.5 * second.Duration()).yaw, M_PI / 2.0, 1e-9);
  EXPECT_NEAR(path.Sample(path.Duration()).yaw, M_PI / 2.0, 1e-9);

  const auto samples = path.SampleEvery(0.05);
  ASSERT_GE(samples.size(), 2u);
  EXPECT_EQ(samples.front().t, 0.0);
  EXPECT_NEAR(samples.back().t, path.Duration(), 1e-12);
  for (std::size_t i = 1; i + 1 < samples.size(); ++i) EXPECT_NEAR(samples[i].t - samples[i - 1].t, 0.05, 1e-12);
  // The corner at (1, 0) is passed at rest: the yaw turns there (within the 0.1 s the speed
  // takes to reach the blend speed) without a jump.
  const auto fine = path.SampleEvery(0.001);
  for (std::size_t i = 1; i < fine.size(); ++i) {
    EXPECT_LT(std::abs(WrapAngle(fine[i].yaw - fine[i - 1].yaw)), 0.05) << fine[i].t;
  }
}

TEST(RootPathTest, PartKeepsTheStates) {
  RootPath path(YawModel{0.1});
  path.Append(RootSegment::Whole(Line({0, 0, 0.45}, {1, 0, 0.45}), 0.0, 0.0));
  path.Append(RootSegment::Whole(Line({1, 0, 0.45}, {1, 1, 0.45}), 0.0, 1.0));
  const double T = path.Duration();
  const RootPath part = path.Part(0.3 * T, 0.8 * T);
  EXPECT_NEAR(part.Duration(), 0.5 * T, 1e-12);
  for (double s : {0.0, 0.1, 0.25, 0.4, 0.5}) {
    const RootPathSample a = part.Sample(s * T);
    const RootPathSample b = path.Sample(0.3 * T + s * T);
    EXPECT_LT((a.p - b.p).norm(), 1e-12);
    EXPECT_LT((a.v - b.v).norm(), 1e-12);
    EXPECT_NEAR(a.yaw, b.yaw, 1e-9);
  }
  EXPECT_TRUE(path.Part(0.5, 0.5).Empty());
}

}  // namespace
}  // namespace rbcp
