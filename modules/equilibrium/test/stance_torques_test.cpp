#include "rbcp/equilibrium/stance_torques.h"

#include <gtest/gtest.h>

#include "rbcp/equilibrium/static_equilibrium.h"

namespace rbcp {
namespace {

const RobotModel& Robot() {
  static const RobotModel model = RobotModel::LoadDefault(std::string(RBCP_SOURCE_DIR) + "/config");
  return model;
}

struct Stance {
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  JointVector q = JointVector::Zero();
  std::vector<StanceFoot> feet;
};

/// The reference standing stance on flat ground at z = 0, without the feet of `skip` legs.
Stance Standing(std::vector<Leg> skip = {}) {
  const RobotModel& robot = Robot();
  Stance s;
  s.q = robot.ReferenceConfiguration();
  s.base.translation() = Eigen::Vector3d(0, 0, robot.NominalBaseHeight());
  for (Leg leg : kAllLegs) {
    if (std::find(skip.begin(), skip.end(), leg) != skip.end()) continue;
    StanceFoot f;
    f.leg = leg;
    f.position_W = s.base * robot.FootPosition(leg, LegJoints(s.q, leg));
    s.feet.push_back(f);
  }
  return s;
}

ForceDistributionParams Params() {
  ForceDistributionParams p;
  p.friction = 0.5;
  p.min_normal_force_N = 20.0;
  return p;
}

TEST(StanceTorquesTest, StandingStanceCarriesTheWeightWithModestTorques) {
  const Stance s = Standing();
  const Eigen::Vector3d com = s.base * Robot().CenterOfMass(s.q);
  const StanceTorques t = ComputeStanceTorques(Robot(), s.base, s.q, s.feet, com, Params());
  ASSERT_TRUE(t.balanced);
  double fz = 0.0;
  for (const Eigen::Vector3d& f : t.forces.forces_W) fz += f.z();
  EXPECT_NEAR(fz, Robot().TotalMass() * kGravity, 0.01 * Robot().TotalMass() * kGravity);
  EXPECT_GT(t.max_abs_Nm, 1.0);
  EXPECT_LT(t.max_abs_Nm, 25.0);
  ASSERT_GE(t.worst_joint, 0);
  EXPECT_DOUBLE_EQ(std::abs(t.tau[t.worst_joint]), t.max_abs_Nm);
}

TEST(StanceTorquesTest, TorquesAreLegWeightMinusJacobianTransposeForce) {
  const Stance s = Standing();
  const RobotModel& robot = Robot();
  const Eigen::Vector3d com = s.base * robot.CenterOfMass(s.q);
  const StanceTorques t = ComputeStanceTorques(robot, s.base, s.q, s.feet, com, Params());
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d q = LegJoints(s.q, leg);
    const Eigen::Vector3d f = t.forces.forces_W[static_cast<std::size_t>(Index(leg))];
    const Eigen::Vector3d expected =
        robot.LegGravityTorques(leg, q, Eigen::Vector3d(0, 0, -kGravity)) - robot.FootJacobian(leg, q).transpose() * f;
    EXPECT_LT((LegJoints(t.tau, leg) - expected).norm(), 1e-9) << LegName(leg);
  }
}

TEST(StanceTorquesTest, ALegNotInStanceHasNoTorqueAndTheOthersCarryMore) {
  const Stance four = Standing();
  const Stance three = Standing({Leg::kLF});
  const RobotModel& robot = Robot();
  // The CoM moved into the triangle of the three feet that stay.
  Eigen::Vector3d com = four.base * robot.CenterOfMass(four.q);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const StanceFoot& f : three.feet) centroid += f.position_W / 3.0;
  com.head<2>() = 0.5 * (com.head<2>() + centroid.head<2>());
  const StanceTorques t4 = ComputeStanceTorques(robot, four.base, four.q, four.feet, com, Params());
  const StanceTorques t3 = ComputeStanceTorques(robot, three.base, three.q, three.feet, com, Params());
  ASSERT_TRUE(t3.balanced);
  EXPECT_EQ(LegJoints(t3.tau, Leg::kLF), Eigen::Vector3d::Zero());
  EXPECT_NE(t3.worst_joint / kJointsPerLeg, Index(Leg::kLF));
  EXPECT_GT(t3.max_abs_Nm, t4.max_abs_Nm);
}

TEST(StanceTorquesTest, ACoMOutsideTheSupportIsNotBalanced) {
  const Stance three = Standing({Leg::kLF});
  // Above the lifted foot: outside the triangle of the other three.
  const Eigen::Vector3d com = three.base * Robot().FootPosition(Leg::kLF, LegJoints(three.q, Leg::kLF)) +
                              Eigen::Vector3d(0, 0, 0.45);
  EXPECT_FALSE(ComputeStanceTorques(Robot(), three.base, three.q, three.feet, com, Params()).balanced);
  EXPECT_FALSE(ComputeStanceTorques(Robot(), three.base, three.q, {}, com, Params()).balanced);
}

}  // namespace
}  // namespace rbcp
