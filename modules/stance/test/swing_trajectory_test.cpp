#include "rbcp/stance/swing_trajectory.h"

#include <gtest/gtest.h>

#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

TriangleMesh Box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TerrainBox box;
  box.size = hi - lo;
  box.position = 0.5 * (lo + hi);
  return ElementMesh(box);
}

TEST(SwingTrajectory, StartsAndEndsAtRestOnItsFootholds) {
  const SwingPathConfig config;
  const Eigen::Vector3d a(0, 0, 0), b(0.2, 0.0, 0.0);
  const SwingTrajectory s =
      SwingTrajectory::Plan(a, b, nullptr, 0.031, config);
  EXPECT_GE(s.Duration(), config.min_duration_s);
  EXPECT_NEAR((s.Position(0.0) - a).norm(), 0.0, 1e-12);
  EXPECT_NEAR((s.Position(s.Duration()) - (b - config.touchdown_depth_m * Eigen::Vector3d::UnitZ())).norm(), 0.0, 1e-12);
  EXPECT_EQ(s.Velocity(0.0).norm(), 0.0);
  EXPECT_EQ(s.Velocity(s.Duration()).norm(), 0.0);
  // The apex is near height_m above the footholds.
  double top = -1.0;
  for (int k = 0; k <= 100; ++k) top = std::max(top, s.Position(s.Duration() * k / 100.0).z());
  EXPECT_NEAR(top, config.height_m, 0.01);
}

TEST(SwingTrajectory, VelocityIsTheDerivativeOfPosition) {
  const SwingTrajectory s = SwingTrajectory::Plan(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 0.1, 0.15), nullptr,
                                                  0.031, SwingPathConfig());
  for (double t = 0.05; t < s.Duration() - 0.05; t += 0.05) {
    const double h = 1e-6;
    const Eigen::Vector3d fd = (s.Position(t + h) - s.Position(t - h)) / (2 * h);
    EXPECT_NEAR((s.Velocity(t) - fd).norm(), 0.0, 1e-6);
  }
}

TEST(SwingTrajectory, RisesOverAnObstacleBetweenTheFootholds) {
  SwingPathConfig config;
  // Ground at z = 0 and a 0.15 m high, 6 cm wide wall half-way.
  TriangleMesh terrain = Box(Eigen::Vector3d(-1, -1, -0.1), Eigen::Vector3d(1, 1, 0.0));
  const TriangleMesh wall = Box(Eigen::Vector3d(0.12, -1, 0.0), Eigen::Vector3d(0.18, 1, 0.15));
  const int offset = static_cast<int>(terrain.vertices.size());
  terrain.vertices.insert(terrain.vertices.end(), wall.vertices.begin(), wall.vertices.end());
  for (auto t : wall.triangles) terrain.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const TerrainHeightMap heights(terrain);
  const SwingTrajectory s = SwingTrajectory::Plan(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 0, 0), &heights, 0.031,
                                                  config);
  EXPECT_GE(s.Clearance(), config.terrain_clearance_m);
  for (int k = 0; k <= 200; ++k) {
    const Eigen::Vector3d p = s.Position(s.Duration() * k / 200.0);
    if (p.x() > 0.12 - 0.031 && p.x() < 0.18 + 0.031) {
      EXPECT_GT(p.z(), 0.15) << "at x = " << p.x();
    }
  }
}

TEST(SwingTrajectory, StepsOntoARiserWithoutTouchingItsEdge) {
  // A 0.17 m step whose riser is 4.5 cm ahead of the lifting foot (as on the plinth).
  SwingPathConfig config;
  TriangleMesh terrain = Box(Eigen::Vector3d(-1, -1, -0.5), Eigen::Vector3d(0.045, 1, 0.0));
  const TriangleMesh step = Box(Eigen::Vector3d(0.045, -1, -0.5), Eigen::Vector3d(1, 1, 0.17));
  const int offset = static_cast<int>(terrain.vertices.size());
  terrain.vertices.insert(terrain.vertices.end(), step.vertices.begin(), step.vertices.end());
  for (auto t : step.triangles) terrain.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const Eigen::Vector3d target(0.13, 0.0, 0.17);
  const TerrainHeightMap heights(terrain);
  const SwingTrajectory s = SwingTrajectory::Plan(Eigen::Vector3d::Zero(), target, &heights, 0.031, config);
  for (int k = 0; k <= 400; ++k) {
    const Eigen::Vector3d p = s.Position(s.Duration() * k / 400.0);
    // The sphere (centre 0.031 above the contact point) stays off the riser's top edge.
    const Eigen::Vector2d centre(p.x(), p.z() + 0.031);
    if (p.z() < 0.17 - 0.011) {
      EXPECT_LT(p.x(), 0.045 - 0.031 + 1e-9) << "k " << k;
    }
    const double edge = (centre - Eigen::Vector2d(0.045, 0.17)).norm();
    if (p.x() < target.x() - 0.03) {
      EXPECT_GT(edge, 0.031) << "k " << k;
    }
  }
  EXPECT_NEAR(s.Position(s.Duration()).x(), target.x(), 1e-12);
}

TEST(SwingTrajectory, RaisesTheApexUntilTheLegIsClear) {
  SwingPathConfig config;
  // A leg check that fails below 0.2 m at the middle of the path.
  const SwingTrajectory::LegCheck clear = [](const Eigen::Vector3d& p) {
    return !(std::abs(p.x() - 0.1) < 0.05 && p.z() < 0.2);
  };
  const SwingTrajectory s = SwingTrajectory::Plan(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0, 0), nullptr, 0.031,
                                                  config, clear);
  EXPECT_EQ(s.LegCollisions(), 0);
  EXPECT_GE(s.Apex(), 0.2);
  EXPECT_LT(s.Apex(), 0.24);
}

TEST(SwingTrajectory, KeepsThePreferredCheckWhereItCanAndTheRequiredOneAlways) {
  SwingPathConfig config;
  const SwingTrajectory::LegCheck clear = [](const Eigen::Vector3d&) { return true; };
  // A preferred check that fails below 0.2 m at the middle of the path: the apex rises over it.
  const SwingTrajectory::LegCheck high = [](const Eigen::Vector3d& p) {
    return !(std::abs(p.x() - 0.1) < 0.05 && p.z() < 0.2);
  };
  const SwingTrajectory raised = SwingTrajectory::Plan(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0, 0), nullptr,
                                                       0.031, config, clear, Eigen::Vector2d::Zero(), high);
  EXPECT_EQ(raised.LegCollisions(), 0);
  EXPECT_EQ(raised.PreferredMisses(), 0);
  EXPECT_GE(raised.Apex(), 0.2);
  // One that fails wherever the foot is lifted cannot be kept: the path is the lowest one.
  const SwingTrajectory::LegCheck never = [](const Eigen::Vector3d&) { return false; };
  const SwingTrajectory plain = SwingTrajectory::Plan(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0, 0), nullptr,
                                                      0.031, config, clear);
  const SwingTrajectory missed = SwingTrajectory::Plan(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0, 0), nullptr,
                                                       0.031, config, clear, Eigen::Vector2d::Zero(), never);
  EXPECT_EQ(missed.LegCollisions(), 0);
  EXPECT_GT(missed.PreferredMisses(), 0);
  EXPECT_EQ(missed.Apex(), plain.Apex());
  // The required check comes first: a path clear of it is kept over one that keeps the preferred.
  const SwingTrajectory::LegCheck low_only = [](const Eigen::Vector3d& p) { return p.z() < 0.15; };
  const SwingTrajectory capped = SwingTrajectory::Plan(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0, 0), nullptr,
                                                       0.031, config, low_only, Eigen::Vector2d::Zero(), high);
  EXPECT_EQ(capped.LegCollisions(), 0);
  EXPECT_LT(capped.Apex(), 0.15);
  EXPECT_GT(capped.PreferredMisses(), 0);
}

TEST(SwingTrajectory, BowsTowardsTheBodyWhenRaisingDoesNotClearTheLeg) {
  // A leg check that fails wherever the lifted foot stays near the straight line (a knee that
  // swings out into a wall beside the robot whatever the apex).
  const SwingTrajectory::LegCheck clear = [](const Eigen::Vector3d& p) {
    return !(std::abs(p.y()) < 0.02 && p.z() > 0.03);
  };
  const SwingTrajectory s = SwingTrajectory::Plan(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0, 0), nullptr, 0.031,
                                                  SwingPathConfig(), clear, Eigen::Vector2d(0, 1));
  EXPECT_EQ(s.LegCollisions(), 0);
  EXPECT_GT(s.Bow().y(), 0.02);
  EXPECT_EQ(s.Bow().x(), 0.0);
}

TEST(SwingTrajectory, DrawsTheFootBackWhenItsKneeWouldMeetTheRiserAhead) {
  // Stepping up onto a block ahead: a foot that rises straight up bends its knee forwards into
  // the block's edge; drawn back while it rises, it keeps the knee behind it.
  const SwingTrajectory::LegCheck clear = [](const Eigen::Vector3d& p) {
    return !(p.z() > 0.05 && p.z() < 0.15 && p.x() > -0.01);
  };
  const SwingTrajectory s = SwingTrajectory::Plan(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.3, 0, 0.2), nullptr, 0.031,
                                                  SwingPathConfig(), clear, Eigen::Vector2d(0, 1));
  EXPECT_EQ(s.LegCollisions(), 0);
  EXPECT_LT(s.Bow().x(), -0.02);
  EXPECT_EQ(s.Bow().y(), 0.0);
  // It still starts and ends on its footholds.
  EXPECT_NEAR((s.Position(0.0) - Eigen::Vector3d::Zero()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(s.Position(s.Duration()).x(), 0.3, 1e-12);
}

}  // namespace
}  // namespace rbcp
