#include "rbcp/equilibrium/force_distribution.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace rbcp {
namespace {

std::vector<StanceFoot> Square(double half_x = 0.35, double half_y = 0.25) {
  std::vector<StanceFoot> feet;
  for (Leg leg : kAllLegs) {
    StanceFoot f;
    f.leg = leg;
    f.position_W = Eigen::Vector3d(ForeSign(leg) * half_x, LeftSign(leg) * half_y, 0.0);
    feet.push_back(f);
  }
  return feet;
}

Wrench Weight(double m) { return (Wrench() << 0, 0, m * 9.81, 0, 0, 0).finished(); }

bool InsideCone(const Eigen::Vector3d& f, const Eigen::Vector3d& n, double mu) {
  const double fn = f.dot(n);
  return fn >= -1e-9 && (f - fn * n).norm() <= mu * fn + 1e-6;
}

TEST(ForceDistribution, SymmetricStanceSharesTheWeightEvenly) {
  const ForceDistributionParams params;
  const ForceDistribution d = DistributeWrench(Square(), Eigen::Vector3d(0, 0, 0.45), Weight(30.0), params);
  for (const Eigen::Vector3d& f : d.forces_W) {
    EXPECT_NEAR(f.z(), 30.0 * 9.81 / 4.0, 0.5);
    EXPECT_TRUE(InsideCone(f, Eigen::Vector3d::UnitZ(), params.friction));
  }
  EXPECT_NEAR((d.achieved - Weight(30.0)).norm(), 0.0, 1.0);
}

TEST(ForceDistribution, OffCentreCoMLoadsTheNearerFeetAndBalancesTheMoment) {
  const ForceDistributionParams params;
  const Eigen::Vector3d com(0.15, 0.05, 0.45);
  const ForceDistribution d = DistributeWrench(Square(), com, Weight(30.0), params);
  EXPECT_GT(d.forces_W[0].z(), d.forces_W[3].z());  // LF carries more than RH
  EXPECT_NEAR((d.achieved - Weight(30.0)).norm(), 0.0, 1.0);
  for (const Eigen::Vector3d& f : d.forces_W) EXPECT_GE(f.z(), params.min_normal_force_N - 1e-6);
}

TEST(ForceDistribution, ALegWithLittleLoadCarriesLittle) {
  ForceDistributionParams params;
  std::vector<StanceFoot> feet = Square();
  feet[0].load = 0.02;  // LF about to lift
  const Eigen::Vector3d com(-0.05, -0.05, 0.45);  // inside the triangle RF, LH, RH
  const ForceDistribution d = DistributeWrench(feet, com, Weight(30.0), params);
  EXPECT_LT(d.forces_W[0].z(), 10.0);
  EXPECT_NEAR(d.achieved[2], 30.0 * 9.81, 2.0);
}

TEST(ForceDistribution, ForcesStayInsideTheConesOnASlope) {
  ForceDistributionParams params;
  std::vector<StanceFoot> feet = Square();
  const Eigen::Vector3d n = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ();
  for (StanceFoot& f : feet) f.normal_W = n;
  const ForceDistribution d = DistributeWrench(feet, Eigen::Vector3d(0, 0, 0.45), Weight(30.0), params);
  for (const Eigen::Vector3d& f : d.forces_W) EXPECT_TRUE(InsideCone(f, n, params.friction));
  EXPECT_NEAR(d.achieved[2], 30.0 * 9.81, 2.0);
  EXPECT_NEAR(d.achieved[0], 0.0, 2.0);
}

TEST(ForceDistribution, NoFeetNoForces) {
  const ForceDistribution d = DistributeWrench({}, Eigen::Vector3d::Zero(), Weight(30.0), ForceDistributionParams());
  for (const Eigen::Vector3d& f : d.forces_W) EXPECT_EQ(f.norm(), 0.0);
}

}  // namespace
}  // namespace rbcp
