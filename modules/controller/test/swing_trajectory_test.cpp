#include "rbcp/controller/swing_trajectory.h"

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
  const SwingConfig config;
  const Eigen::Vector3d a(0, 0, 0), b(0.2, 0.0, 0.0);
  const SwingTrajectory s =
      SwingTrajectory::Plan(a, Eigen::Vector3d::UnitZ(), b, Eigen::Vector3d::UnitZ(), nullptr, 0.031, config);
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
  const SwingTrajectory s = SwingTrajectory::Plan(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitZ(),
                                                  Eigen::Vector3d(0.3, 0.1, 0.15), Eigen::Vector3d::UnitZ(), nullptr,
                                                  0.031, SwingConfig());
  for (double t = 0.05; t < s.Duration() - 0.05; t += 0.05) {
    const double h = 1e-6;
    const Eigen::Vector3d fd = (s.Position(t + h) - s.Position(t - h)) / (2 * h);
    EXPECT_NEAR((s.Velocity(t) - fd).norm(), 0.0, 1e-6);
  }
}

TEST(SwingTrajectory, RisesOverAnObstacleBetweenTheFootholds) {
  SwingConfig config;
  // Ground at z = 0 and a 0.15 m high, 6 cm wide wall half-way.
  TriangleMesh terrain = Box(Eigen::Vector3d(-1, -1, -0.1), Eigen::Vector3d(1, 1, 0.0));
  const TriangleMesh wall = Box(Eigen::Vector3d(0.12, -1, 0.0), Eigen::Vector3d(0.18, 1, 0.15));
  const int offset = static_cast<int>(terrain.vertices.size());
  terrain.vertices.insert(terrain.vertices.end(), wall.vertices.begin(), wall.vertices.end());
  for (auto t : wall.triangles) terrain.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const SwingTrajectory s = SwingTrajectory::Plan(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitZ(),
                                                  Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d::UnitZ(), &terrain,
                                                  0.031, config);
  EXPECT_GE(s.Clearance(), config.terrain_clearance_m);
  for (int k = 0; k <= 200; ++k) {
    const Eigen::Vector3d p = s.Position(s.Duration() * k / 200.0);
    if (p.x() > 0.12 - 0.031 && p.x() < 0.18 + 0.031) {
      EXPECT_GT(p.z(), 0.15) << "at x = " << p.x();
    }
  }
}

}  // namespace
}  // namespace rbcp
