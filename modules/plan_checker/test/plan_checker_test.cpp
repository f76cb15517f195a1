#include "rbcp/plan_checker/plan_checker.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

#include "flat_ground_plan.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/pose.h"
#include "rbcp/stance/dynamic_walk.h"

namespace rbcp {
namespace {

using test::BuildFlatGroundPlan;
using test::Describe;
using test::FlatGroundWorld;
using test::SolveJoints;
using test::ViolationSet;

PlanCheckReport Check(const ContactPlan& plan, const PlanCheckConfig& config) {
  const auto& w = FlatGroundWorld::Get();
  return CheckPlan(w.robot, w.scenario.terrain_mesh, w.surfaces, plan, config);
}
PlanCheckReport Check(const ContactPlan& plan) { return Check(plan, FlatGroundWorld::Get().config); }

bool Has(const PlanCheckReport& report, int state, const std::string& check) {
  return ViolationSet(report).count({state, check}) > 0;
}

FootContact& Foot(WholeBodyState& state, Leg leg) { return state.feet[static_cast<std::size_t>(Index(leg))]; }

class PlanCheckerTest : public ::testing::Test {
 protected:
  const FlatGroundWorld& world = FlatGroundWorld::Get();
  ContactPlan plan = BuildFlatGroundPlan(FlatGroundWorld::Get().robot);
};

TEST_F(PlanCheckerTest, ConfigFromThePlannersConfigs) {
  const EquilibriumConfig eq = EquilibriumConfig::LoadFile(test::ConfigDir() + "/equilibrium.yaml");
  const PlanCheckConfig config = PlanCheckConfig::FromConfigs(world.robot, eq, StanceRules::LoadFromDir(test::ConfigDir()));
  EXPECT_EQ(config.robustness_threshold_N, eq.robustness_threshold_N);
  EXPECT_EQ(config.support_margin_m, StanceRules::LoadFromDir(test::ConfigDir()).config.support_margin_m);
  EXPECT_EQ(config.torque_limit_Nm, world.robot.ContinuousTorqueLimit());
  EXPECT_EQ(config.equilibrium.friction, eq.friction);
  EXPECT_NO_THROW(config.Validate());
}

TEST_F(PlanCheckerTest, ValidHandBuiltPlanPasses) {
  ASSERT_EQ(plan.states.size(), 9u);
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(report.ok) << Describe(report);
  EXPECT_EQ(report.violation_count, 0);
  EXPECT_EQ(report.states, 9);
  // Four feet on flat ground with the CoM well inside: robust, modest torques, and every swing
  // keeps the CoM inside its stance triangle by the configured margin.
  EXPECT_GE(report.min_robustness_N, world.config.robustness_threshold_N);
  EXPECT_GT(report.max_torque_Nm, 1.0);
  EXPECT_LE(report.max_torque_Nm, world.config.torque_limit_Nm);
  EXPECT_GE(report.min_support_margin_m, world.config.support_margin_m);
  EXPECT_TRUE(std::isfinite(report.min_support_margin_m));
  EXPECT_NE(report.Summary().find("plan passes: 9 states"), std::string::npos) << report.Summary();
}

TEST_F(PlanCheckerTest, FootAboveTheGroundIsOffItsSurface) {
  // The last step's foot lands 2 cm above the ground, with joints that reach it.
  WholeBodyState& last = plan.states.back();
  const Leg swing = kAllLegs[static_cast<std::size_t>(last.moving_leg)];
  Foot(last, swing).position.z() += 0.02;
  SolveJoints(world.robot, last);
  const PlanCheckReport report = Check(plan);
  const int i = static_cast<int>(plan.states.size()) - 1;
  EXPECT_FALSE(report.ok);
  EXPECT_EQ(ViolationSet(report), (std::set<std::pair<int, std::string>>{{i, "surface"}})) << Describe(report);
  EXPECT_NE(report.violations.front().detail.find(std::string(LegName(swing)) + " foot"), std::string::npos);
  EXPECT_NE(report.violations.front().detail.find("0.0200 m from its plane"), std::string::npos)
      << report.violations.front().detail;
}

TEST_F(PlanCheckerTest, FootWithinTheSurfaceToleranceIsOnIt) {
  WholeBodyState& last = plan.states.back();
  Foot(last, kAllLegs[static_cast<std::size_t>(last.moving_leg)]).position.z() += 0.0009;
  SolveJoints(world.robot, last);
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(report.ok) << Describe(report);
}

TEST_F(PlanCheckerTest, FootNormalDifferentFromTheSurfaceNormal) {
  WholeBodyState& last = plan.states.back();
  Foot(last, kAllLegs[static_cast<std::size_t>(last.moving_leg)]).normal =
      Eigen::Vector3d(0.1, 0.0, 1.0).normalized();
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(Has(report, static_cast<int>(plan.states.size()) - 1, "surface")) << Describe(report);
  EXPECT_NE(report.violations.front().detail.find("normal difference"), std::string::npos);
}

TEST_F(PlanCheckerTest, FootOffEverySurface) {
  // State 3's swing foot put beyond the floor's side edge (the floor spans y in [-1.5, 1.5]).
  Foot(plan.states[3], kAllLegs[static_cast<std::size_t>(plan.states[3].moving_leg)]).position.y() = 1.6;
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(Has(report, 3, "surface")) << Describe(report);
  bool outside = false;
  for (const auto& v : report.violations) {
    outside = outside || (v.state == 3 && v.check == "surface" && v.detail.find("outside its polygon") != std::string::npos);
  }
  EXPECT_TRUE(outside) << Describe(report);
  EXPECT_TRUE(Has(report, 3, "fk")) << Describe(report);  // the joints were left where they were
}

TEST_F(PlanCheckerTest, NoSurfacesAtAll) {
  const auto& w = world;
  const PlanCheckReport report = CheckPlan(w.robot, w.scenario.terrain_mesh, {}, plan, w.config);
  EXPECT_EQ(report.violation_count, 4 * static_cast<int>(plan.states.size())) << Describe(report);
  for (const auto& v : report.violations) {
    EXPECT_EQ(v.check, "surface");
    EXPECT_NE(v.detail.find("no contact surfaces"), std::string::npos);
  }
}

TEST_F(PlanCheckerTest, TwoLegsMovingInOneStep) {
  WholeBodyState& last = plan.states.back();
  const int i = static_cast<int>(plan.states.size()) - 1;
  const Leg swing = kAllLegs[static_cast<std::size_t>(last.moving_leg)];
  const Leg other = swing == Leg::kLF ? Leg::kRF : Leg::kLF;
  Foot(last, other).position.x() += 0.05;
  SolveJoints(world.robot, last);
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(Has(report, i, "one_leg")) << Describe(report);
  for (const auto& v : report.violations) {
    if (v.check == "one_leg") {
      EXPECT_NE(v.detail.find("2 feet change their contact"), std::string::npos) << v.detail;
    }
  }
}

TEST_F(PlanCheckerTest, MovingLegMustNameTheLegThatSteps) {
  plan.states[2].moving_leg = (plan.states[2].moving_leg + 1) % kNumLegs;
  plan.states[0].moving_leg = Index(Leg::kRH);
  plan.states[4].moving_leg = -1;
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(Has(report, 0, "one_leg")) << Describe(report);
  EXPECT_TRUE(Has(report, 2, "one_leg")) << Describe(report);
  EXPECT_TRUE(Has(report, 4, "one_leg")) << Describe(report);
  EXPECT_FALSE(Has(report, 1, "one_leg"));
  EXPECT_FALSE(Has(report, 3, "one_leg"));
}

TEST_F(PlanCheckerTest, AStateWhereNoLegSteps) {
  // A repeated state: nothing changes its contact.
  plan.states.push_back(plan.states.back());
  const PlanCheckReport report = Check(plan);
  const int i = static_cast<int>(plan.states.size()) - 1;
  EXPECT_TRUE(Has(report, i, "one_leg")) << Describe(report);
  EXPECT_NE(report.violations.front().detail.find("no foot changes its contact"), std::string::npos);
}

TEST_F(PlanCheckerTest, JointsInconsistentWithFeet) {
  plan.states[1].joints[kJointsPerLeg * Index(Leg::kRH) + 1] += 0.1;  // RH_HFE
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(Has(report, 1, "fk")) << Describe(report);
  for (const auto& v : report.violations) {
    if (v.check == "fk") {
      EXPECT_EQ(v.state, 1);
      EXPECT_NE(v.detail.find("RH joints"), std::string::npos) << v.detail;
      EXPECT_EQ(v.detail.find("LF joints"), std::string::npos) << v.detail;
    }
  }
}

TEST_F(PlanCheckerTest, FkToleranceIsSubMillimetre) {
  Foot(plan.states[5], Leg::kLH).position.x() += 0.5e-4;  // within 1e-4
  EXPECT_TRUE(Check(plan).ok);
  Foot(plan.states[5], Leg::kLH).position.x() += 1e-4;  // now 1.5e-4 off
  const PlanCheckReport report = Check(plan);
  EXPECT_EQ(ViolationSet(report), (std::set<std::pair<int, std::string>>{{5, "fk"}})) << Describe(report);
}

TEST_F(PlanCheckerTest, JointsOutsideThePlanningBounds) {
  // LF KFE must stay <= 0 (knees in X); a positive value is outside the bounds.
  plan.states[6].joints[kJointsPerLeg * Index(Leg::kLF) + 2] = 0.2;
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(Has(report, 6, "joint_bounds")) << Describe(report);
  for (const auto& v : report.violations) {
    if (v.check == "joint_bounds" && v.state == 6) {
      EXPECT_NE(v.detail.find("LF_KFE"), std::string::npos) << v.detail;
    }
  }
}

TEST_F(PlanCheckerTest, StretchedLegsLeaveTheKinematicMargins) {
  // The trunk raised over the same feet, a centimetre at a time: the legs leave the margins
  // (too far from their hips, or the knees too straight) while they still reach their feet.
  const KinematicMargins& margins = world.robot.Margins();
  bool left = false;
  for (int cm = 1; cm <= 25 && !left; ++cm) {
    ContactPlan raised = plan;
    WholeBodyState& s = raised.states[4];
    s.base_position.z() += 0.01 * cm;
    bool reachable = true;
    for (Leg leg : kAllLegs) {
      const Eigen::Vector3d p_B = BasePose(s).inverse() * s.feet[static_cast<std::size_t>(Index(leg))].position;
      reachable = reachable && world.robot.SolveLegIk(leg, p_B).ok();
    }
    ASSERT_TRUE(reachable) << "out of reach at +" << cm << " cm before leaving the margins";
    SolveJoints(world.robot, s);
    const PlanCheckReport report = Check(raised);
    if (!Has(report, 4, "kinematic_margin")) continue;
    left = true;
    EXPECT_GE(cm, 3) << Describe(report);  // the reference stance is well inside
    for (const auto& v : report.violations) {
      if (v.check != "kinematic_margin" || v.state != 4) continue;
      const bool far = v.detail.find("m from its hip, at most " + FixedNumber(margins.max_stance_hip_distance_m, 4) +
                                     " m") != std::string::npos;
      const bool straight = v.detail.find("rad, at least " + FixedNumber(margins.min_knee_bend_rad, 4) + " rad") !=
                            std::string::npos;
      EXPECT_TRUE(far || straight) << v.detail;
    }
    EXPECT_FALSE(Has(report, 4, "joint_bounds")) << Describe(report);
    EXPECT_FALSE(Has(report, 3, "kinematic_margin")) << Describe(report);
  }
  EXPECT_TRUE(left);
}

TEST_F(PlanCheckerTest, BaseLoweredIntoTheGroundCollides) {
  plan.states[2].base_position.z() = 0.10;
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(Has(report, 2, "collision")) << Describe(report);
  for (const auto& v : report.violations) {
    if (v.check == "collision") {
      EXPECT_EQ(v.state, 2);
      EXPECT_NE(v.detail.find("terrain"), std::string::npos) << v.detail;
    }
  }
  // Without the collision check only the kinematic consequences remain.
  PlanCheckConfig config = world.config;
  config.check_collision = false;
  EXPECT_FALSE(Has(Check(plan, config), 2, "collision"));
}

TEST_F(PlanCheckerTest, CollisionCheckToleratesTheStanceFeet) {
  // Feet on the ground every state and the check on: the valid plan has no collision at all.
  const PlanCheckReport report = Check(plan);
  for (const auto& v : report.violations) EXPECT_NE(v.check, "collision") << v.detail;
  EXPECT_TRUE(report.ok);
}

TEST_F(PlanCheckerTest, CrossedFrontLegsCollideWithEachOther) {
  // The front feet swapped sides under the trunk (joints consistent): the lower legs cross.
  WholeBodyState& last = plan.states.back();
  Foot(last, Leg::kLF).position.y() = last.base_position.y() - 0.08;
  Foot(last, Leg::kRF).position.y() = last.base_position.y() + 0.08;
  SolveJoints(world.robot, last);
  const PlanCheckReport report = Check(plan);
  const int i = static_cast<int>(plan.states.size()) - 1;
  EXPECT_TRUE(Has(report, i, "self_collision")) << Describe(report);
  for (const auto& v : report.violations) {
    if (v.check == "self_collision") {
      EXPECT_EQ(v.state, i);
      EXPECT_NE(v.detail.find(" hits "), std::string::npos) << v.detail;
    }
  }
  PlanCheckConfig config = world.config;
  config.check_collision = false;
  EXPECT_FALSE(Has(Check(plan, config), i, "self_collision"));
}

TEST_F(PlanCheckerTest, CoMFarOutsideTheSupportTriangle) {
  // State 1 (after the LF step): the base moved 15 cm towards the swing foot, joints consistent.
  WholeBodyState& state = plan.states[1];
  ASSERT_EQ(state.moving_leg, Index(Leg::kLF));
  state.base_position += Eigen::Vector3d(0.10, 0.11, 0.0);
  SolveJoints(world.robot, state);
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(Has(report, 1, "support_margin")) << Describe(report);
  int outside = 0;
  for (const auto& v : report.violations) {
    if (v.check == "support_margin") {
      EXPECT_EQ(v.state, 1);
      EXPECT_NE(v.detail.find("support triangle of RF, LH, RH"), std::string::npos) << v.detail;
      if (v.detail.find("outside") != std::string::npos) ++outside;
    }
  }
  EXPECT_EQ(outside, 2) << "both at lift-off and at touchdown: " << Describe(report);
  EXPECT_LT(report.min_support_margin_m, 0.0);
}

TEST_F(PlanCheckerTest, CentredCoMOnTheStanceDiagonalLacksMargin) {
  // Stepping without first shifting the body: the CoM stays near the diagonal of the stance
  // triangle, which leaves no margin.
  ContactPlan centred;
  centred.states.push_back(plan.states[0]);
  WholeBodyState step = plan.states[0];
  step.moving_leg = Index(Leg::kLF);
  Foot(step, Leg::kLF).position.x() += 0.10;
  SolveJoints(world.robot, step);
  centred.states.push_back(step);
  const PlanCheckReport report = Check(centred);
  EXPECT_TRUE(Has(report, 1, "support_margin")) << Describe(report);
  EXPECT_LT(report.min_support_margin_m, world.config.support_margin_m);
  EXPECT_GT(report.min_support_margin_m, -0.03);
}

TEST_F(PlanCheckerTest, SwingLegThatCannotKeepItsFootholdUntilLiftOff) {
  // The trunk of state 1 is 40 cm further back: LF, still on its old foothold at lift-off, is out
  // of reach. (The joints are left as they were, so FK fails too; the lift-off reach is the point.)
  plan.states[1].base_position.x() -= 0.40;
  const PlanCheckReport report = Check(plan);
  bool lift_off = false;
  for (const auto& v : report.violations) {
    lift_off = lift_off || (v.state == 1 && v.check == "joint_bounds" && v.detail.find("lift-off") != std::string::npos &&
                            v.detail.find("LF cannot keep its foothold of state 0") != std::string::npos);
  }
  EXPECT_TRUE(lift_off) << Describe(report);
  EXPECT_TRUE(Has(report, 1, "fk"));
}

TEST_F(PlanCheckerTest, StabilityThreshold) {
  PlanCheckConfig config = world.config;
  const PlanCheckReport valid = Check(plan, config);
  ASSERT_TRUE(valid.ok);
  config.robustness_threshold_N = valid.min_robustness_N + 0.01;  // just above the weakest state
  const PlanCheckReport report = Check(plan, config);
  // The weakest states (shifted bodies) fail; the centred start stance is more robust and passes.
  ASSERT_GE(report.violation_count, 1) << Describe(report);
  EXPECT_LT(report.violation_count, report.states) << Describe(report);
  EXPECT_FALSE(Has(report, 0, "stability")) << Describe(report);
  for (const auto& v : report.violations) {
    EXPECT_EQ(v.check, "stability");
    EXPECT_NE(v.detail.find("expected at least"), std::string::npos);
  }
}

TEST_F(PlanCheckerTest, UnbalancedStanceIsUnstable) {
  // The right feet pulled under the left side of the trunk (joints consistent): all four feet lie
  // left of the CoM, so gravity cannot be balanced.
  WholeBodyState& last = plan.states.back();
  const double left_y = Foot(last, Leg::kLH).position.y();
  Foot(last, Leg::kRF).position.y() = left_y - 0.12;
  Foot(last, Leg::kRH).position.y() = left_y - 0.12;
  SolveJoints(world.robot, last);
  const PlanCheckReport report = Check(plan);
  const int i = static_cast<int>(plan.states.size()) - 1;
  EXPECT_TRUE(Has(report, i, "stability")) << Describe(report);
  EXPECT_LT(report.min_robustness_N, 0.0);
}

TEST_F(PlanCheckerTest, TorqueLimit) {
  PlanCheckConfig config = world.config;
  const PlanCheckReport valid = Check(plan, config);
  ASSERT_TRUE(valid.ok);
  config.torque_limit_Nm = valid.max_torque_Nm - 0.01;
  const PlanCheckReport report = Check(plan, config);
  ASSERT_GE(report.violation_count, 1) << Describe(report);
  for (const auto& v : report.violations) {
    EXPECT_EQ(v.check, "torque");
    EXPECT_NE(v.detail.find("over the limit"), std::string::npos);
  }
  // Torques scale with the weight: a tenth of the limit fails every state on four feet, every
  // step's three-foot stance at lift-off and its shift (at the first pose checked, which ends it).
  config.torque_limit_Nm = 0.1 * valid.max_torque_Nm;
  const PlanCheckReport low = Check(plan, config);
  const int steps = static_cast<int>(plan.states.size()) - 1;
  EXPECT_EQ(low.violation_count, 3 * steps + 1) << Describe(low);
  int lift_off = 0, shift = 0;
  for (const auto& v : low.violations) {
    lift_off += v.detail.rfind("at lift-off ", 0) == 0 ? 1 : 0;
    shift += v.detail.find("of the shift from state") != std::string::npos ? 1 : 0;
  }
  EXPECT_EQ(lift_off, steps);
  EXPECT_EQ(shift, steps);
}

TEST_F(PlanCheckerTest, TorquesOfTheThreeFootStanceAtLiftOff) {
  // The lift-off stance carries the weight on three feet: its torques exceed the four-foot ones,
  // and a limit between the two fails it alone.
  PlanCheckConfig config = world.config;
  config.torque_limit_Nm = 1e3;
  const PlanCheckReport valid = Check(plan, config);
  ASSERT_TRUE(valid.ok) << Describe(valid);
  double four_foot = 0.0;  // the largest torque of the states on four feet, each checked alone
  for (const WholeBodyState& state : plan.states) {
    ContactPlan one;
    one.states = {state};
    one.states[0].moving_leg = -1;
    four_foot = std::max(four_foot, Check(one, config).max_torque_Nm);
  }
  ASSERT_GT(valid.max_torque_Nm, four_foot + 1.0);
  config.torque_limit_Nm = four_foot + 0.5;
  const PlanCheckReport report = Check(plan, config);
  ASSERT_GE(report.violation_count, 1) << Describe(report);
  for (const auto& v : report.violations) {
    EXPECT_EQ(v.check, "torque");
    EXPECT_EQ(v.detail.rfind("at lift-off ", 0), 0u) << v.detail;
  }
}

TEST_F(PlanCheckerTest, EveryViolationIsCountedButOnlyTheFirstAreKept) {
  PlanCheckConfig config = world.config;
  config.max_violations = 5;
  config.torque_limit_Nm = 0.5;  // every state fails, every lift-off and every shift
  config.robustness_threshold_N = 1e4;  // every state fails
  const PlanCheckReport report = Check(plan, config);
  EXPECT_EQ(report.violation_count, 4 * static_cast<int>(plan.states.size()) - 2);
  EXPECT_EQ(report.violations.size(), 5u);
  EXPECT_EQ(report.violations[0].state, 0);
  EXPECT_EQ(report.violations[0].check, "stability");
  EXPECT_EQ(report.violations[1].state, 0);
  EXPECT_EQ(report.violations[1].check, "torque");
  EXPECT_NE(report.Summary().find("plan fails: 34 violations in 9 states (stability, torque)"), std::string::npos)
      << report.Summary();
}

TEST_F(PlanCheckerTest, BadInputThrows) {
  EXPECT_THROW(Check(ContactPlan{}), InputError);
  ContactPlan bad = plan;
  bad.states[3].joints[4] = std::nan("");
  EXPECT_THROW(Check(bad), InputError);
  PlanCheckConfig unset;  // thresholds not taken from the configs
  try {
    Check(plan, unset);
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("robustness_threshold_N"), std::string::npos) << e.what();
  }
}

TEST_F(PlanCheckerTest, ASwingThroughAWallFailsTheSwingCheck) {
  // A 0.3 m high, 2 cm thin wall half-way between LF's footholds of states 0 and 1: the swing
  // the state carries (8 cm high) passes through it, though every stance stands clear of it.
  const auto& w = FlatGroundWorld::Get();
  ASSERT_EQ(plan.states[1].moving_leg, Index(Leg::kLF));
  const Eigen::Vector3d from = plan.states[0].feet[static_cast<std::size_t>(Index(Leg::kLF))].position;
  const Eigen::Vector3d to = plan.states[1].feet[static_cast<std::size_t>(Index(Leg::kLF))].position;
  TerrainBox wall;
  wall.size = Eigen::Vector3d(0.02, 0.1, 0.3);
  wall.position = 0.5 * (from + to) + Eigen::Vector3d(0, 0, 0.15);
  TriangleMesh terrain = w.scenario.terrain_mesh;
  terrain.Append(ElementMesh(wall));
  ContactPlan two;
  two.states = {plan.states[0], plan.states[1]};
  two.states[1].swing_apex_z = from.z() + 0.08;
  const PlanCheckReport report = CheckPlan(w.robot, terrain, w.surfaces, two, w.config);
  EXPECT_TRUE(Has(report, 1, "swing")) << Describe(report);
  EXPECT_FALSE(Has(report, 0, "collision")) << Describe(report);
  // On the flat floor alone the same swing is clear.
  EXPECT_FALSE(Has(Check(two), 1, "swing"));
}

TEST_F(PlanCheckerTest, ReportAsJson) {
  PlanCheckConfig config = world.config;
  config.torque_limit_Nm = 0.5;
  const nlohmann::json j = PlanCheckReportToJson(Check(plan, config));
  EXPECT_EQ(j["ok"], false);
  EXPECT_EQ(j["states"], 9);
  EXPECT_EQ(j["violation_count"], 25);  // 9 states on four feet, 8 lift-offs, 8 shifts
  EXPECT_EQ(j["violations"][0]["check"], "torque");
  EXPECT_EQ(j["violations"][0]["state"], 0);
  EXPECT_TRUE(j["min_support_margin_m"].is_number());
  ContactPlan single;
  single.states.push_back(plan.states[0]);
  const nlohmann::json one = PlanCheckReportToJson(Check(single));
  EXPECT_EQ(one["ok"], true);
  EXPECT_TRUE(one["min_support_margin_m"].is_null());  // no swing: +infinity
}

TEST_F(PlanCheckerTest, ATimedPlanIsCheckedAlongItsDynamicWalk) {
  StanceChecker stance(world.robot, world.config.stance);
  stance.SetTerrain(&world.scenario.terrain_mesh);
  TimeDynamicWalk(stance, &plan);
  ASSERT_TRUE(plan.Timed());
  const PlanCheckReport report = Check(plan);
  EXPECT_TRUE(report.ok) << Describe(report);
  EXPECT_TRUE(report.timed);
  EXPECT_TRUE(report.walk_violations.empty()) << report.walk_violations.front().detail;
  EXPECT_GT(report.min_zmp_margin_m, 0.0);
  EXPECT_LT(report.min_zmp_margin_m, 0.5);
  EXPECT_GT(report.max_walk_torque_Nm, 1.0);
  const nlohmann::json j = PlanCheckReportToJson(report);
  EXPECT_EQ(j["walk"]["ok"], true);
  EXPECT_TRUE(j["walk"]["min_zmp_margin_m"].is_number());

  // The walk's torques are held to the stance rules' ceiling: below what the walk asks, the walk
  // fails, while the plan's own states (held to the actuators' limit) still pass.
  PlanCheckConfig strict = world.config;
  strict.stance.config.torque_limit_fraction = 0.5 * report.max_walk_torque_Nm / world.robot.ContinuousTorqueLimit();
  const PlanCheckReport strained = Check(plan, strict);
  EXPECT_TRUE(strained.ok) << Describe(strained);
  ASSERT_FALSE(strained.walk_violations.empty()) << strained.Summary();
  EXPECT_EQ(strained.walk_violations.front().check, "walk");
  EXPECT_NE(strained.walk_violations.front().detail.find("torque"), std::string::npos);
  EXPECT_NE(strained.Summary().find("steps fail a check"), std::string::npos) << strained.Summary();

  // A lift-off before the previous touch-down is no clock at all.
  ContactPlan backwards = plan;
  backwards.states[3].lift_off_s = backwards.states[2].lift_off_s;
  const PlanCheckReport bad = Check(backwards);
  EXPECT_FALSE(bad.ok);
  EXPECT_TRUE(Has(bad, 0, "timing")) << Describe(bad);
  EXPECT_FALSE(bad.timed);

  // An untimed plan has no walk to check.
  EXPECT_TRUE(PlanCheckReportToJson(Check(BuildFlatGroundPlan(world.robot)))["walk"].is_null());
}

TEST(PlanCheckerScenarioTest, CheckPlanForScenarioMatchesCheckPlan) {
  const auto& w = FlatGroundWorld::Get();
  const ContactPlan plan = BuildFlatGroundPlan(w.robot, 4);
  const PlanCheckReport direct = CheckPlan(w.robot, w.scenario.terrain_mesh, w.surfaces, plan, w.config);
  const PlanCheckReport loaded = CheckPlanForScenario(test::ConfigDir(), w.scenario, plan);
  EXPECT_TRUE(loaded.ok) << Describe(loaded);
  EXPECT_EQ(loaded.min_robustness_N, direct.min_robustness_N);
  EXPECT_EQ(loaded.max_torque_Nm, direct.max_torque_Nm);
  EXPECT_EQ(loaded.min_support_margin_m, direct.min_support_margin_m);
}

}  // namespace
}  // namespace rbcp
