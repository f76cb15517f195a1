#include "rbcp/stance/stance_checker.h"

#include <gtest/gtest.h>

#include "rbcp/core/pose.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

const std::string kConfigDir = std::string(RBCP_SOURCE_DIR) + "/config";

const RobotModel& Robot() {
  static const RobotModel robot = RobotModel::LoadDefault(kConfigDir);
  return robot;
}

StanceChecker Checker(const StanceConfig& config = StanceConfig::LoadFile(kConfigDir + "/stance.yaml")) {
  StanceRules rules = StanceRules::LoadFromDir(kConfigDir);
  rules.config = config;
  return StanceChecker(Robot(), rules);
}

TriangleMesh Box(const Eigen::Vector3d& size, const Eigen::Vector3d& centre) {
  TerrainBox box;
  box.size = size;
  box.position = centre;
  return ElementMesh(box);
}

TriangleMesh Floor() { return Box({4, 3, 0.5}, {0, 0, -0.25}); }

/// Every leg's joints by inverse kinematics of the state's feet at its base pose.
void SolveJoints(WholeBodyState& s) {
  for (Leg leg : kAllLegs) {
    const IkResult ik = Robot().SolveLegIk(leg, BasePose(s).inverse() * s.feet[static_cast<std::size_t>(Index(leg))].position);
    ASSERT_TRUE(ik.ok()) << LegName(leg) << ": " << ik.reason;
    SetLegJoints(s.joints, leg, ik.q);
  }
}

/// The robot standing on flat ground in its reference configuration.
WholeBodyState Standing() {
  WholeBodyState s;
  s.base_position = Eigen::Vector3d(0, 0, Robot().NominalBaseHeight());
  s.joints = Robot().ReferenceConfiguration();
  for (Leg leg : kAllLegs) {
    s.feet[static_cast<std::size_t>(Index(leg))].position = s.base_position + Robot().FootPosition(leg, LegJoints(s.joints, leg));
  }
  return s;
}

/// `from` with `leg` stepped `step` forward; with `shift_base` the base moves so that the CoM lies
/// half-way from the centroid of the four feet to that of the three that stay.
WholeBodyState Step(const WholeBodyState& from, Leg leg, double step, bool shift_base) {
  WholeBodyState to = from;
  to.moving_leg = Index(leg);
  to.feet[static_cast<std::size_t>(Index(leg))].position.x() += step;
  Eigen::Vector2d all = Eigen::Vector2d::Zero(), stay = Eigen::Vector2d::Zero();
  for (Leg other : kAllLegs) {
    const Eigen::Vector2d p = from.feet[static_cast<std::size_t>(Index(other))].position.head<2>();
    all += p / 4.0;
    if (other != leg) stay += p / 3.0;
  }
  const Eigen::Vector2d target = 0.5 * (all + stay);
  for (int k = 0; k < (shift_base ? 4 : 1); ++k) {
    SolveJoints(to);
    if (!shift_base) break;
    const Eigen::Vector3d com = BasePose(to) * Robot().CenterOfMass(to.joints);
    to.base_position.head<2>() += target - com.head<2>();
  }
  SolveJoints(to);
  return to;
}

TEST(StanceChecker, AStepOnFlatGroundPassesEveryPhase) {
  StanceChecker checker = Checker();
  const TriangleMesh floor = Floor();
  checker.SetTerrain(&floor);
  const WholeBodyState from = Standing();
  const WholeBodyState to = Step(from, Leg::kLF, 0.1, true);
  const StanceVerdict v = checker.CheckStep(from, to);
  EXPECT_TRUE(v.ok()) << v.Describe();
}

TEST(StanceChecker, ALiftOffWithoutTheBodyShiftFailsOnSupport) {
  StanceChecker checker = Checker();
  const TriangleMesh floor = Floor();
  checker.SetTerrain(&floor);
  const WholeBodyState from = Standing();
  const StanceVerdict v = checker.CheckStep(from, Step(from, Leg::kLF, 0.1, false));
  EXPECT_EQ(v.check, StanceCheck::kSupport) << v.Describe();
  EXPECT_EQ(v.phase, StepPhase::kLiftOff) << v.Describe();
}

TEST(StanceChecker, TorquesAboveTheCeilingFailTheShift) {
  StanceConfig config = StanceConfig::LoadFile(kConfigDir + "/stance.yaml");
  config.torque_limit_fraction = 0.1;  // 4 N m: less than a standing knee needs
  const StanceChecker checker = Checker(config);
  const WholeBodyState from = Standing();
  const StanceVerdict v = checker.CheckStep(from, Step(from, Leg::kLF, 0.1, true));
  EXPECT_EQ(v.check, StanceCheck::kTorque) << v.Describe();
  EXPECT_EQ(v.phase, StepPhase::kShift) << v.Describe();
  ASSERT_TRUE(v.leg.has_value());
  EXPECT_NE(v.detail.find("static torque"), std::string::npos) << v.detail;
}

TEST(StanceChecker, AWallTooHighToSwingOverBlocksTheSwing) {
  StanceChecker checker = Checker();
  const WholeBodyState from = Standing();
  const WholeBodyState to = Step(from, Leg::kLF, 0.12, true);
  const Eigen::Vector3d lf = from.feet[static_cast<std::size_t>(Index(Leg::kLF))].position;
  // A 0.6 m wall, 2 cm thick, half-way between the old and the new foothold, in front of LF only.
  TriangleMesh terrain = Floor();
  terrain.Append(Box({0.02, 0.2, 0.6}, {lf.x() + 0.06, lf.y() + 0.05, 0.3}));
  checker.SetTerrain(&terrain);
  const StanceVerdict v = checker.CheckStep(from, to);
  EXPECT_EQ(v.check, StanceCheck::kSwingTerrain) << v.Describe();
  EXPECT_EQ(v.phase, StepPhase::kSwing) << v.Describe();
  EXPECT_EQ(v.leg, Leg::kLF);
}

TEST(StanceChecker, AStanceLegOnABlockIsNamedAtLiftOff) {
  StanceChecker checker = Checker();
  const WholeBodyState from = Standing();
  const WholeBodyState to = Step(from, Leg::kLF, 0.1, true);
  const Eigen::Vector3d rh = from.feet[static_cast<std::size_t>(Index(Leg::kRH))].position;
  TriangleMesh terrain = Floor();
  terrain.Append(Box({0.08, 0.08, 0.08}, rh + Eigen::Vector3d(0, 0, 0.15)));  // around RH's shank
  checker.SetTerrain(&terrain);
  const StanceVerdict v = checker.CheckStep(from, to);
  EXPECT_EQ(v.check, StanceCheck::kCollision) << v.Describe();
  EXPECT_EQ(v.leg, Leg::kRH) << v.Describe();
}

TEST(StanceChecker, WithoutATerrainTheSwingIsThePlainPath) {
  const StanceChecker checker = Checker();
  EXPECT_FALSE(checker.HasTerrain());
  const WholeBodyState from = Standing();
  const WholeBodyState to = Step(from, Leg::kRF, 0.1, true);
  const std::size_t i = static_cast<std::size_t>(Index(Leg::kRF));
  const SwingTrajectory s = checker.PlanSwing(Leg::kRF, from.feet[i].position, to.feet[i].position, BasePose(to), to.joints);
  EXPECT_TRUE(s.TerrainClear());
  EXPECT_EQ(s.LegCollisions(), 0);
  EXPECT_NEAR(s.Apex(), from.feet[i].position.z() + checker.Config().swing.height_m, 1e-12);
}

TEST(StanceChecker, TheTorqueCeilingIsTheFractionOfTheCommandLimit) {
  const StanceChecker checker = Checker();
  EXPECT_DOUBLE_EQ(checker.TorqueCeiling(), 0.85 * Robot().ContinuousTorqueLimit());
  EXPECT_EQ(std::string(ToString(StanceCheck::kSwingBody)), "swing_body");
  EXPECT_EQ(std::string(ToString(StepPhase::kTouchDown)), "touch_down");
}

}  // namespace
}  // namespace rbcp
