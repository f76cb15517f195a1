#include "rbcp/equilibrium/friction_cone.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

Eigen::Vector3d Tilted(double tilt_rad, double heading_rad) {
  // Normal of a plane rising towards heading_rad (in the xy plane) with inclination tilt_rad.
  return Eigen::Vector3d(-std::sin(tilt_rad) * std::cos(heading_rad), -std::sin(tilt_rad) * std::sin(heading_rad),
                         std::cos(tilt_rad));
}

TEST(FrictionCone, GeneratorsLieOnTheCoulombConeAroundTheNormal) {
  for (double mu : {0.3, 0.5, 1.2}) {
    for (int count : {3, 4, 8}) {
      for (const Eigen::Vector3d& n : {Eigen::Vector3d::UnitZ().eval(), Tilted(0.5, 0.3), Tilted(1.2, -2.0),
                                       Eigen::Vector3d::UnitX().eval(), Eigen::Vector3d(0, 0, -1)}) {
        const Eigen::Matrix3Xd g = FrictionConeGenerators(3.0 * n, mu, count);
        ASSERT_EQ(g.cols(), count);
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (int j = 0; j < count; ++j) {
          EXPECT_NEAR(g.col(j).norm(), 1.0, 1e-12);
          const double fn = g.col(j).dot(n);
          const double ft = (g.col(j) - fn * n).norm();
          EXPECT_NEAR(ft, mu * fn, 1e-12) << "mu " << mu << " count " << count;
          sum += g.col(j);
        }
        // The generators are symmetric about the normal.
        EXPECT_NEAR((sum - count / std::sqrt(1 + mu * mu) * n).norm(), 0.0, 1e-12);
        // The reference's b0 -> e_max conversion |sum x G_0|.
        EXPECT_NEAR(sum.cross(g.col(0)).norm(), RobustnessPerGeneratorWeight(mu, count), 1e-12);
      }
    }
  }
}

TEST(FrictionCone, FirstEdgePointsUpTheSlope) {
  const Eigen::Vector3d n = Tilted(0.4, 0.7);  // rises towards heading 0.7 rad
  const Eigen::Matrix3Xd g = FrictionConeGenerators(n, 0.5, 4);
  // G_0 lies in the vertical plane through n and the up-slope direction, on the uphill side.
  const Eigen::Vector3d uphill(std::cos(0.7), std::sin(0.7), 0.0);
  EXPECT_NEAR(g.col(0).dot(uphill.cross(Eigen::Vector3d::UnitZ())), 0.0, 1e-12);
  EXPECT_GT(g.col(0).dot(uphill), n.dot(uphill));
  for (int j = 1; j < 4; ++j) EXPECT_GT(g.col(0).z(), g.col(j).z());
  // Opposite edges are mirror images about the normal.
  EXPECT_NEAR((g.col(0) + g.col(2) - 2 * g.col(0).dot(n) * n).norm(), 0.0, 1e-12);
}

TEST(FrictionCone, TangentsFormARightHandedFrame) {
  for (const Eigen::Vector3d& n : {Eigen::Vector3d::UnitZ().eval(), Tilted(0.3, 2.0), Eigen::Vector3d::UnitX().eval(),
                                   Eigen::Vector3d(0, 0, -1)}) {
    Eigen::Vector3d t1, t2;
    ContactTangents(n, &t1, &t2);
    EXPECT_NEAR(t1.norm(), 1.0, 1e-12);
    EXPECT_NEAR(t2.norm(), 1.0, 1e-12);
    EXPECT_NEAR(t1.dot(n), 0.0, 1e-12);
    EXPECT_NEAR((t1.cross(t2) - n).norm(), 0.0, 1e-12);
  }
  Eigen::Vector3d t1, t2;
  ContactTangents(Eigen::Vector3d::UnitZ(), &t1, &t2);
  EXPECT_NEAR((t1 - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-12);
}

TEST(FrictionCone, RejectsBadInput) {
  EXPECT_THROW(FrictionConeGenerators(Eigen::Vector3d::Zero(), 0.5, 4), InputError);
  EXPECT_THROW(FrictionConeGenerators(Eigen::Vector3d(0, NAN, 1), 0.5, 4), InputError);
  EXPECT_THROW(FrictionConeGenerators(Eigen::Vector3d::UnitZ(), 0.0, 4), InputError);
  EXPECT_THROW(FrictionConeGenerators(Eigen::Vector3d::UnitZ(), 0.5, 2), InputError);
}

}  // namespace
}  // namespace rbcp
