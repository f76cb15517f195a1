// The controller walking plans in the simulated world, judged by the simulator. Every run here
// is a few seconds of simulated time; the long runs are in the benchmark.
#include "rbcp/sim/plan_execution.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <tuple>
#include <sstream>

#include "flat_ground_plan.h"
#include "rbcp/controller/controller_config.h"
#include "rbcp/plan_checker/plan_json.h"

namespace rbcp::sim {
namespace {

using rbcp::test::BuildFlatGroundPlan;
using rbcp::test::ConfigDir;
using rbcp::test::ScenarioPath;

struct Models {
  RobotModel robot = RobotModel::LoadDefault(ConfigDir());
  SimConfig sim = SimConfig::LoadFile(ConfigDir() + "/sim.yaml");
  ControllerConfig controller = ControllerConfig::LoadFile(ConfigDir() + "/controller.yaml");
  StanceRules stance = StanceRules::LoadFromDir(ConfigDir());
};

const Models& Get() {
  static const Models setup;
  return setup;
}

/// The shipped controller configuration in mode dynamic.
ControllerConfig DynamicWalk() {
  ControllerConfig dynamic = Get().controller;
  dynamic.mode = WalkMode::kDynamic;
  return dynamic;
}

/// The shipped robot with another continuous torque limit [N m]: its planning parameters written
/// to a file of their own with that one line changed.
RobotModel RobotWithTorqueLimit(double limit_Nm) {
  std::ifstream in(ConfigDir() + "/robots/anymal_b.yaml");
  std::string text;
  int replaced = 0;
  for (std::string line; std::getline(in, line);) {
    const bool limit = line.rfind("continuous_torque_limit:", 0) == 0;
    replaced += limit ? 1 : 0;
    std::ostringstream changed;
    changed << "continuous_torque_limit: " << limit_Nm;
    text += (limit ? changed.str() : line) + "\n";
  }
  EXPECT_EQ(replaced, 1) << "the robot file names its continuous torque limit once";
  const std::string path = ::testing::TempDir() + "/anymal_b_torque_limit.yaml";
  std::ofstream(path) << text;
  return RobotModel::Load(ConfigDir() + "/robots/anymal_b.urdf", path);
}

/// What ended a run, for the message of a failed expectation.
std::string Why(const ExecutionOutcome& o) {
  return o.failure ? o.failure->what + ": " + o.failure->detail : std::string("not reached");
}

/// flat_ground's floor with a hole through it: 0.12 x 0.16 m centred on `hole_xy`.
Scenario FloorWithHole(const Eigen::Vector2d& hole_xy) {
  Scenario s = LoadScenario(ScenarioPath("flat_ground"));
  const double x0 = -1.75, x1 = 6.75, y0 = -1.5, y1 = 1.5, hx = 0.06, hy = 0.08;
  auto box = [](double ax, double bx, double ay, double by) {
    TerrainBox b;
    b.size = Eigen::Vector3d(bx - ax, by - ay, 0.5);
    b.position = Eigen::Vector3d(0.5 * (ax + bx), 0.5 * (ay + by), -0.25);
    return TerrainElement(b);
  };
  s.terrain = {box(x0, hole_xy.x() - hx, y0, y1), box(hole_xy.x() + hx, x1, y0, y1),
               box(hole_xy.x() - hx, hole_xy.x() + hx, y0, hole_xy.y() - hy),
               box(hole_xy.x() - hx, hole_xy.x() + hx, hole_xy.y() + hy, y1)};
  s.terrain_mesh = BuildTerrainMesh(s.terrain);
  return s;
}

TEST(PlanExecution, StandingWithoutAPlanHoldsTheBaseWithinOneCentimetre) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  PlanExecution run(g.robot, scenario, g.sim, g.controller, g.stance);
  run.StandAt(scenario.start);
  // Let the drop settle, then measure the drift over 10 s.
  while (run.Time() < 0.5) run.Tick();
  const Eigen::Vector3d settled = run.State().base_position_W;
  while (run.Time() < 10.5) run.Tick();
  const RobotState end = run.State();
  EXPECT_LT((end.base_position_W - settled).norm(), 0.01);
  for (bool c : end.foot_contact) EXPECT_TRUE(c);
  EXPECT_EQ(run.Controller().Status().phase, ControllerPhase::kHold);
}

TEST(PlanExecution, AShortFlatGroundPlanReachesItsGoal) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const ContactPlan plan = BuildFlatGroundPlan(g.robot, 4, 0.08);
  PlanExecution run(g.robot, scenario, g.sim, g.controller, g.stance);
  run.Start(plan);
  const ExecutionOutcome& o = run.Run();
  ASSERT_TRUE(o.ok()) << Why(o);
  EXPECT_EQ(o.steps_executed, 4);
  EXPECT_LT(o.final_base_error_m, g.sim.outcome.goal_tolerance_m);
  EXPECT_LE(o.max_torque_ratio, 1.0);
  EXPECT_EQ(o.collisions, 0);
  EXPECT_GT(o.trace.size(), 20u);
  // The feet end where the plan put them.
  for (Leg leg : kAllLegs) {
    const std::size_t i = static_cast<std::size_t>(Index(leg));
    EXPECT_LT((o.trace.back().feet[i] - plan.states.back().feet[i].position).head<2>().norm(), 0.03) << LegName(leg);
  }
}

TEST(PlanExecution, TheDynamicWalkMovesTheBaseWhileALegSwingsInLessThanHalfTheCrawlsTime) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const ContactPlan plan = BuildFlatGroundPlan(g.robot, 8, 0.08);
  PlanExecution walk(g.robot, scenario, g.sim, DynamicWalk(), g.stance);
  walk.Start(plan);
  // Over every swing the base moves on; the centre of pressure of the feet stays inside the
  // three feet down.
  double least_swing_motion_m = 1e9;
  std::optional<Eigen::Vector3d> swing_start;
  ControllerPhase last = ControllerPhase::kHold;
  int most_committed = 0;  // steps after the current one the preview prepares for
  while (walk.Tick()) {
    const ControllerPhase phase = walk.Controller().Status().phase;
    most_committed = std::max(most_committed, walk.Controller().CommittedSteps());
    const Eigen::Vector3d base = walk.State().base_position_W;
    if (phase == ControllerPhase::kSwing && last != ControllerPhase::kSwing) swing_start = base;
    if (phase != ControllerPhase::kSwing && last == ControllerPhase::kSwing && swing_start) {
      least_swing_motion_m = std::min(least_swing_motion_m, (base - *swing_start).head<2>().norm());
    }
    last = phase;
  }
  const ExecutionOutcome& o = walk.Outcome();
  ASSERT_TRUE(o.ok()) << Why(o);
  EXPECT_EQ(o.steps_executed, 8);
  EXPECT_LT(o.final_base_error_m, g.sim.outcome.goal_tolerance_m);
  EXPECT_LE(o.max_torque_ratio, 1.0);
  EXPECT_EQ(o.collisions, 0);
  EXPECT_GT(least_swing_motion_m, 0.01);
  ASSERT_NE(walk.Controller().Pattern(), nullptr);
  EXPECT_GT(walk.Controller().Pattern()->MinZmpMargin(), 0.0);
  EXPECT_LT(walk.Controller().Status().lag_s, 0.05);  // the feet kept to the clock
  // A step lasts about a second; the 1.6 s preview reaches into the next step or two.
  EXPECT_GE(most_committed, 1);
  EXPECT_LE(most_committed, 3);
  EXPECT_EQ(walk.Controller().CommittedSteps(), 0);  // none after the last step

  // The static crawl of the same plan takes more than twice as long in simulated time.
  PlanExecution crawl(g.robot, scenario, g.sim, g.controller, g.stance);
  crawl.Start(plan);
  while (crawl.Tick()) ASSERT_EQ(crawl.Controller().CommittedSteps(), 0);  // the crawl commits to nothing ahead
  const ExecutionOutcome& c = crawl.Outcome();
  ASSERT_TRUE(c.ok()) << Why(c);
  EXPECT_LT(2.0 * o.sim_time_s, c.sim_time_s);
}

/// The dynamic walk of `plan` on `scenario`, pushed sideways (world y) with `force_N` for 0.2 s
/// from `at_s`.
ExecutionOutcome WalkPushed(const Scenario& scenario, const ContactPlan& plan, double at_s, double force_N) {
  const Models& g = Get();
  PlanExecution run(g.robot, scenario, g.sim, DynamicWalk(), g.stance);
  run.Start(plan);
  while (run.Time() < at_s && run.Tick()) {
  }
  run.SetBaseForce(Eigen::Vector3d(0.0, force_N, 0.0));
  while (run.Time() < at_s + 0.2 && run.Tick()) {
  }
  run.SetBaseForce(Eigen::Vector3d::Zero());
  return run.Run();
}

/// A push of 60 N for 0.2 s to either side, at a time into the walk.
class PushRecovery : public ::testing::TestWithParam<std::tuple<double, double>> {};

TEST_P(PushRecovery, OnFlatGroundTheWalkGoesOn) {
  const auto [at_s, force_N] = GetParam();
  const ContactPlan plan = BuildFlatGroundPlan(Get().robot, 8, 0.08);
  const ExecutionOutcome o = WalkPushed(LoadScenario(ScenarioPath("flat_ground")), plan, at_s, force_N);
  EXPECT_TRUE(o.ok()) << Why(o);
  EXPECT_EQ(o.steps_executed, 8);
}

TEST_P(PushRecovery, UpThePlinthsStairsTheWalkGoesOn) {
  const auto [at_s, force_N] = GetParam();
  const ContactPlan plan = LoadContactPlanFile(std::string(RBCP_SOURCE_DIR) + "/tests/data/plinth_stairs_up.json");
  const ExecutionOutcome o = WalkPushed(LoadScenario(ScenarioPath("plinth")), plan, at_s, force_N);
  EXPECT_TRUE(o.ok()) << Why(o);
  EXPECT_EQ(o.steps_executed, 10);
}

// Pushes to either side at four times into the walk, in swings and between them. Pushed towards
// the leg in the air, the trunk tips over the edge of the support triangle (on flat ground at
// 2.2 s, on the stairs at 3.1 s and 4.0 s): without the swing's hurry to put the foot down and
// the stance servo's fading on an unloaded foot, a stance foot slides.
INSTANTIATE_TEST_SUITE_P(SixtyNewtons, PushRecovery,
                         ::testing::Combine(::testing::Values(1.3, 2.2, 3.1, 4.0), ::testing::Values(-60.0, 60.0)));

TEST(PlanExecution, APlanWalkedWholeReachesTheScenarioGoalOnlyWhereItEnds) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));  // goal 5 m ahead
  ContactPlan plan = BuildFlatGroundPlan(g.robot, 1, 0.08);
  plan.states.resize(1);  // stand where it starts
  PlanExecution run(g.robot, scenario, g.sim, g.controller, g.stance);
  run.Start(plan);
  ExecutionOutcome o = run.Run();
  ASSERT_TRUE(o.ok()) << "the plan of one state is walked at once: " << Why(o);
  JudgeAgainstGoal(o, plan, scenario.goal, 0.3);
  EXPECT_FALSE(o.reached_goal);
  ASSERT_TRUE(o.failure.has_value());
  EXPECT_EQ(o.failure->what, "short_of_goal");
  EXPECT_NE(o.failure->detail.find("ends 5.00 m from the scenario's goal"), std::string::npos) << o.failure->detail;
  // Where the plan ends at the goal, the verdict stands.
  BaseGoal here = scenario.goal;
  here.position = plan.states.back().base_position.head<2>() + Eigen::Vector2d(0.2, 0.0);
  ExecutionOutcome at_goal = run.Outcome();
  JudgeAgainstGoal(at_goal, plan, here, 0.3);
  EXPECT_TRUE(at_goal.ok()) << Why(at_goal);
}

TEST(PlanExecution, AHindLegSteppingDownFromCloseBelowItsHipKeepsItsThighOffTheTrunk) {
  // On the plinth's stairs, going down: LH steps from the second tread, 0.21 m below its hip, to
  // the first. A swing path that lifts the foot straight up folds the thigh against the trunk and
  // the hip flexion stalls at its torque limit; the controller's path keeps the leg clear.
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("plinth"));
  const ContactPlan plan =
      LoadContactPlanFile(std::string(RBCP_SOURCE_DIR) + "/tests/data/plinth_hind_step_down.json");
  ASSERT_EQ(plan.states.size(), 2u);
  ASSERT_EQ(plan.states[1].moving_leg, Index(Leg::kLH));
  PlanExecution run(g.robot, scenario, g.sim, g.controller, g.stance);
  run.Start(plan);
  const ExecutionOutcome& o = run.Run();
  ASSERT_TRUE(o.ok()) << Why(o);
  EXPECT_EQ(o.steps_executed, 1);
  EXPECT_LT(o.max_torque_ratio, 1.0);
}

class PlanReplacement : public ::testing::TestWithParam<WalkMode> {};

TEST_P(PlanReplacement, ANewPlanReplacesTheRestAtAStepBoundary) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const ContactPlan first = BuildFlatGroundPlan(g.robot, 6, 0.08);
  ControllerConfig controller = g.controller;
  controller.mode = GetParam();
  PlanExecution run(g.robot, scenario, g.sim, controller, g.stance);
  run.Start(first);
  // During the first step's swing a plan arrives that goes on from the stance after that step.
  while (run.Controller().Status().phase != ControllerPhase::kSwing) ASSERT_TRUE(run.Tick());
  // Its first state is the stance that step leaves; then LF steps back to 4 cm ahead of the
  // reference stance, and RH and RF step 4 cm.
  ContactPlan second = BuildFlatGroundPlan(g.robot, 3, 0.04);
  second.states.front() = first.states[1];
  run.GivePlan(second);
  EXPECT_EQ(run.Controller().Status().step, 1);  // the step under way goes on
  const ExecutionOutcome& o = run.Run();
  ASSERT_TRUE(o.ok()) << Why(o);
  // One step of the first plan, then the second plan's steps after its first state.
  EXPECT_EQ(run.Controller().Status().steps_done, 1 + 3);
  EXPECT_LT((o.trace.back().base_position - second.states.back().base_position).head<2>().norm(), 0.1);
}

INSTANTIATE_TEST_SUITE_P(BothModes, PlanReplacement, ::testing::Values(WalkMode::kStatic, WalkMode::kDynamic),
                         [](const ::testing::TestParamInfo<WalkMode>& info) {
                           return info.param == WalkMode::kStatic ? "static" : "dynamic";
                         });

TEST(PlanExecution, UpTheStairsTheDynamicWalkInPiecesWalksAsTheWholePlan) {
  // The replanning loop hands the controller a new piece of plan at every step boundary. The rest
  // of the same plan, handed over piece by piece, is walked as the whole plan is: in the same
  // time, the joints as far from their torque limit (a piece taken when a foot touched down
  // early used to start the next shift at once, at the torque limit for 20 ms).
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("plinth"));
  const ContactPlan plan = LoadContactPlanFile(std::string(RBCP_SOURCE_DIR) + "/tests/data/plinth_stairs_up.json");
  std::array<double, 2> time_s{}, torque_ratio{};
  for (int pieces = 0; pieces < 2; ++pieces) {
    PlanExecution run(g.robot, scenario, g.sim, DynamicWalk(), g.stance);
    run.SetAwaitPlans(pieces == 1);
    run.Start(plan);
    while (run.Tick()) {
      // Past the drop onto the terrain at the start.
      if (run.Time() > 0.5) {
        torque_ratio[pieces] = std::max(torque_ratio[pieces], run.State().tau.cwiseAbs().maxCoeff() / g.robot.ContinuousTorqueLimit());
      }
      if (pieces == 1 && run.Awaiting()) {
        ContactPlan rest;
        rest.states.assign(plan.states.begin() + run.Controller().Status().steps_done, plan.states.end());
        rest.states.front().MarkAsStart();
        if (rest.states.size() > 1) {
          run.GivePlan(rest);
        } else {
          run.ContinuePlan();
        }
      }
    }
    ASSERT_TRUE(run.Outcome().ok()) << Why(run.Outcome());
    time_s[pieces] = run.Outcome().sim_time_s;
  }
  EXPECT_NEAR(time_s[1], time_s[0], 0.05);
  EXPECT_LT(torque_ratio[1], torque_ratio[0] + 0.05);
  EXPECT_LT(torque_ratio[1], 0.95);
}

TEST(PlanExecution, APieceOfPlanThatStepsElsewhereIsWalkedFromRest) {
  // At a step boundary of the dynamic walk a piece of plan comes that does not take the step the
  // CoM was headed for (the map changed and the planner started again from the measured stance):
  // the crawl turns back. The CoM comes to rest over its capture point first, then walks the
  // piece from rest as the planner checked it; it went on from the ZMP it followed, which asked
  // for tens of m/s^2 and held the hind legs at the torque limit while a foot slid.
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const ContactPlan forward = BuildFlatGroundPlan(g.robot, 8, 0.08);
  constexpr int kTurnAfter = 3;
  // Back the way it came: the legs that stepped, in the reverse order, to their earlier footholds.
  ContactPlan back;
  for (int i = kTurnAfter; i >= 0; --i) {
    WholeBodyState s = forward.states[static_cast<std::size_t>(i)];
    if (i == kTurnAfter) {
      s.MarkAsStart();
    } else {
      s.moving_leg = forward.states[static_cast<std::size_t>(i) + 1].moving_leg;
    }
    back.states.push_back(s);
  }
  back.reaches_goal = false;
  ASSERT_NE(back.states[1].moving_leg, forward.states[kTurnAfter + 1].moving_leg);
  PlanExecution run(g.robot, scenario, g.sim, DynamicWalk(), g.stance);
  run.SetAwaitPlans(true);
  run.Start(forward);
  double torque_ratio = 0.0;
  bool turned = false;
  while (run.Tick()) {
    if (run.Time() > 0.5) {
      torque_ratio = std::max(torque_ratio, run.State().tau.cwiseAbs().maxCoeff() / g.robot.ContinuousTorqueLimit());
    }
    if (!run.Awaiting()) continue;
    if (run.Controller().Status().steps_done == kTurnAfter && !turned) {
      run.GivePlan(back);
      turned = true;
    } else if (run.Controller().Status().steps_done >= kTurnAfter + 3) {
      break;  // back where it started
    } else {
      run.ContinuePlan();
    }
  }
  ASSERT_TRUE(turned);
  ASSERT_FALSE(run.Outcome().failure) << Why(run.Outcome());
  EXPECT_EQ(run.Controller().Status().steps_done, kTurnAfter + 3);
  EXPECT_LT(torque_ratio, 0.95);
}

TEST(PlanExecution, AFootThatRollsOverItsContactHasNotSlipped) {
  // As the trunk moves over a stance foot, its sphere rolls: the centre moves by the radius times
  // the shank's rotation without any sliding. The judge measures the sliding only.
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const ContactPlan plan = BuildFlatGroundPlan(g.robot, 4, 0.08);
  PlanExecution run(g.robot, scenario, g.sim, g.controller, g.stance);
  run.Start(plan);
  // The LH foot stands until the fourth step; follow its centre and its rotation meanwhile.
  const std::size_t lh = static_cast<std::size_t>(Index(Leg::kLH));
  while (run.Controller().Status().steps_done < 1) ASSERT_TRUE(run.Tick());
  const Eigen::Isometry3d start = run.World().FootFramesW()[lh];
  double moved = 0.0, turned = 0.0;
  while (run.Controller().Status().steps_done < 3) {
    ASSERT_TRUE(run.Tick());
    const Eigen::Isometry3d now = run.World().FootFramesW()[lh];
    moved = std::max(moved, (now.translation() - start.translation()).head<2>().norm());
    turned = std::max(turned, Eigen::AngleAxisd(now.linear() * start.linear().transpose()).angle());
  }
  const ExecutionOutcome& o = run.Run();
  ASSERT_TRUE(o.ok()) << Why(o);
  EXPECT_GT(turned, 0.05);                    // the shank turned over the foot ...
  EXPECT_GT(moved, 0.5 * g.robot.FootRadius() * turned);  // ... and the sphere rolled with it
  EXPECT_LT(o.max_slip_m, 0.5 * moved);       // without sliding as far
}

TEST(PlanExecution, FeetOnIceSlideAndTheJudgeSaysFootSlip) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  SimConfig ice = g.sim;
  ice.physics.friction = 0.05;
  PlanExecution run(g.robot, scenario, ice, g.controller, g.stance);
  run.Start(BuildFlatGroundPlan(g.robot, 4, 0.08));
  const ExecutionOutcome& o = run.Run();
  ASSERT_TRUE(o.failure.has_value());
  EXPECT_EQ(o.failure->what, "foot_slip") << o.failure->detail;
  EXPECT_NE(o.failure->detail.find("slid"), std::string::npos) << o.failure->detail;
  EXPECT_GT(o.max_slip_m, g.sim.outcome.max_slip_m);
  // The stance check that should have caught it: the friction the force distribution assumes.
  EXPECT_NE(o.failure->should_have_caught.find(": balance"), std::string::npos) << o.failure->should_have_caught;
}

TEST(PlanExecution, TheTraceCarriesJointsTorquesAndTheSupportMargin) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const ContactPlan plan = BuildFlatGroundPlan(g.robot, 2, 0.08);
  PlanExecution run(g.robot, scenario, g.sim, g.controller, g.stance);
  run.Start(plan);
  const ExecutionOutcome& o = run.Run();
  ASSERT_TRUE(o.ok()) << Why(o);
  int three_feet = 0, four_feet = 0;
  for (const TraceSample& s : o.trace) {
    const int in_contact = static_cast<int>(std::count(s.contact.begin(), s.contact.end(), true));
    EXPECT_EQ(std::isnan(s.support_margin_m), in_contact < 3) << "t " << s.t;
    // The crawl keeps the CoM inside the feet in contact (a drop and touchdowns aside).
    if (in_contact == 3 && s.phase == "swing") {
      ++three_feet;
      EXPECT_GT(s.support_margin_m, 0.0) << "t " << s.t;
    }
    if (in_contact == 4) ++four_feet;
    EXPECT_LE(s.torques.cwiseAbs().maxCoeff(), g.robot.ContinuousTorqueLimit() + 1e-9);
  }
  EXPECT_GT(three_feet, 0);
  EXPECT_GT(four_feet, 0);
  // Standing at the end: the measured joints near the plan's last, torques holding the weight.
  const TraceSample& last = o.trace.back();
  EXPECT_LT((last.joints - plan.states.back().joints).cwiseAbs().maxCoeff(), 0.1);
  EXPECT_GT(last.torques.cwiseAbs().maxCoeff(), 1.0);

  const nlohmann::json j = TraceSampleToJson(last);
  ASSERT_EQ(j.at("joints").size(), 12u);
  ASSERT_EQ(j.at("torques").size(), 12u);
  EXPECT_NEAR(j.at("joints")[5].get<double>(), last.joints[5], 1e-5);
  EXPECT_NEAR(j.at("torques")[5].get<double>(), last.torques[5], 1e-3);
  EXPECT_NEAR(j.at("support_margin_m").get<double>(), last.support_margin_m, 1e-12);
  EXPECT_EQ(j.at("phase"), last.phase);
  EXPECT_EQ(j.at("feet").size(), 4u);
  // The static crawl has no walking pattern: no CoM or ZMP reference; its centre of pressure is
  // measured all the same.
  for (const TraceSample& s : o.trace) {
    EXPECT_FALSE(s.com_reference.allFinite()) << "t " << s.t;
    EXPECT_FALSE(s.zmp_reference.allFinite()) << "t " << s.t;
  }
  EXPECT_TRUE(j.at("com_reference").is_null());
  EXPECT_TRUE(j.at("zmp_reference").is_null());
  ASSERT_EQ(j.at("cop").size(), 2u);
  EXPECT_NEAR(j.at("cop")[0].get<double>(), last.cop.x(), 1e-12);
}

TEST(PlanExecution, TheDynamicWalksTraceCarriesItsCoMAndZmpReferencesAndTheCentreOfPressure) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const ContactPlan plan = BuildFlatGroundPlan(g.robot, 2, 0.08);
  PlanExecution walk(g.robot, scenario, g.sim, DynamicWalk(), g.stance);
  walk.Start(plan);
  const ExecutionOutcome& o = walk.Run();
  ASSERT_TRUE(o.ok()) << Why(o);
  int with_references = 0, with_cop = 0, loaded = 0;
  for (const TraceSample& s : o.trace) {
    const int in_contact = static_cast<int>(std::count(s.contact.begin(), s.contact.end(), true));
    EXPECT_EQ(s.com_reference.allFinite(), s.zmp_reference.allFinite()) << "t " << s.t;
    if (s.com_reference.allFinite()) {
      ++with_references;
      // The CoM the controller steers to is under the trunk, the ZMP reference near it.
      EXPECT_LT((s.com_reference - s.base_position.head<2>()).norm(), 0.2) << "t " << s.t;
      EXPECT_LT((s.zmp_reference - s.com_reference).norm(), 0.3) << "t " << s.t;
    }
    if (in_contact < 3) {
      EXPECT_FALSE(s.cop.allFinite()) << "t " << s.t;
    } else {
      ++loaded;
    }
    if (s.cop.allFinite()) ++with_cop;
  }
  EXPECT_GT(with_references, static_cast<int>(o.trace.size()) / 2);
  EXPECT_GT(with_cop, loaded / 2);
  // In JSON: [x, y] arrays, as measured.
  const auto sample = std::find_if(o.trace.begin(), o.trace.end(), [](const TraceSample& s) {
    return s.com_reference.allFinite() && s.cop.allFinite();
  });
  ASSERT_NE(sample, o.trace.end());
  const nlohmann::json j = TraceSampleToJson(*sample);
  for (const char* key : {"com_reference", "zmp_reference", "cop"}) ASSERT_EQ(j.at(key).size(), 2u) << key;
  EXPECT_NEAR(j.at("com_reference")[1].get<double>(), sample->com_reference.y(), 1e-12);
  EXPECT_NEAR(j.at("zmp_reference")[0].get<double>(), sample->zmp_reference.x(), 1e-12);
  EXPECT_NEAR(j.at("cop")[1].get<double>(), sample->cop.y(), 1e-12);
}

TEST(PlanExecution, TwoRunsGiveTheSameTrace) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const ContactPlan plan = BuildFlatGroundPlan(g.robot, 2, 0.08);
  auto trace = [&] {
    PlanExecution run(g.robot, scenario, g.sim, g.controller, g.stance);
    run.Start(plan);
    return OutcomeToJson(run.Run()).dump();
  };
  EXPECT_EQ(trace(), trace());
}

TEST(PlanExecution, AFootholdThatIsNotThereEndsTheRunAsNoGround) {
  const Models& g = Get();
  const ContactPlan plan = BuildFlatGroundPlan(g.robot, 4, 0.08);
  // The plan was made on the whole floor; the world lacks the floor under the first step's foot.
  const WholeBodyState& first_step = plan.states[1];
  const Eigen::Vector2d hole = first_step.feet[static_cast<std::size_t>(first_step.moving_leg)].position.head<2>();
  PlanExecution run(g.robot, FloorWithHole(hole), g.sim, g.controller, g.stance);
  run.Start(plan);
  const ExecutionOutcome& o = run.Run();
  ASSERT_TRUE(o.failure.has_value());
  EXPECT_FALSE(o.reached_goal);
  EXPECT_EQ(o.failure->what, "no_ground") << o.failure->detail;
  EXPECT_EQ(o.failure->step, 1);
  EXPECT_EQ(o.failure->leg, std::string(LegName(static_cast<Leg>(first_step.moving_leg))));
  EXPECT_EQ(o.failure->should_have_caught.rfind("swing: reach", 0), 0u) << o.failure->should_have_caught;
}

TEST(PlanExecution, WithoutTorquesTheRobotCollapsesAndTheJudgeSaysFall) {
  const Models& g = Get();
  const Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
  const RobotModel limp = RobotWithTorqueLimit(1e-9);  // the controller commands (next to) nothing ...
  SimConfig patient = g.sim;
  patient.outcome.max_saturation_s = 100.0;  // ... which is not to count as saturation here,
  patient.outcome.max_slip_m = 1.0;          // nor the feet sliding apart as it sinks
  PlanExecution run(limp, scenario, patient, g.controller, g.stance);
  run.Start(BuildFlatGroundPlan(g.robot, 4, 0.08));
  const ExecutionOutcome& o = run.Run();
  ASSERT_TRUE(o.failure.has_value());
  EXPECT_TRUE(o.fell()) << o.failure->what << ": " << o.failure->detail;
  EXPECT_LT(o.failure->t, 3.0);
}

}  // namespace
}  // namespace rbcp::sim

