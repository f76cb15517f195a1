#include "rbcp/transport/convert.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <limits>

#include "rbcp/core/error.h"

namespace rbcp::transport {
namespace {

TEST(Convert, TerrainRoundTrip) {
  TriangleMesh box = MakeBoxMesh({1.0, 2.0, 0.5});
  const auto msg = ToTerrainMsg(box, 42, "box");
  EXPECT_EQ(msg.utime, 42);
  EXPECT_EQ(msg.scenario_name, "box");
  EXPECT_EQ(msg.num_triangles, 12);
  const TriangleMesh back = FromTerrainMsg(msg);
  ASSERT_EQ(back.vertices.size(), box.vertices.size());
  for (std::size_t i = 0; i < box.vertices.size(); ++i) EXPECT_EQ(back.vertices[i], box.vertices[i]);
  EXPECT_EQ(back.triangles, box.triangles);
  EXPECT_EQ(msg.terrain_id, TerrainId(box));
}

TEST(Convert, MalformedTerrainIsRejectedWithAReason) {
  auto msg = ToTerrainMsg(MakeBoxMesh({1, 1, 1}), 0, "");
  auto bad = msg;
  bad.num_triangles = 13;
  EXPECT_THROW(FromTerrainMsg(bad), InputError);
  bad = msg;
  bad.vertices[2][1] = std::numeric_limits<double>::quiet_NaN();
  try {
    FromTerrainMsg(bad);
    FAIL() << "NaN accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "terrain mesh: vertex 2 is not finite");
  }
  bad = msg;
  bad.triangles[0][0] = 100;
  EXPECT_THROW(FromTerrainMsg(bad), InputError);
  bad = msg;
  bad.num_triangles = 0;
  bad.triangles.clear();
  EXPECT_THROW(FromTerrainMsg(bad), InputError);
}

TEST(Convert, RobotStateRoundTripAndValidation) {
  RobotState state;
  state.t = 1.2345;
  state.base_position_W = {1, 2, 0.45};
  state.base_orientation_W = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(0, 0.6, 0.8)));
  state.base_linear_velocity_W = {0.1, -0.2, 0.3};
  state.base_angular_velocity_B = {-0.4, 0.5, 0.6};
  for (int j = 0; j < kNumJoints; ++j) {
    state.q[j] = 0.1 * j;
    state.qd[j] = -0.2 * j;
    state.tau[j] = 1.5 * j;
  }
  state.foot_contact = {true, false, true, true};
  state.foot_force_W[2] = {3, 4, 70};
  const RobotState back = FromRobotStateMsg(ToRobotStateMsg(state));
  EXPECT_EQ(ToRobotStateMsg(state).utime, 1234500);
  EXPECT_DOUBLE_EQ(back.t, 1.2345);
  EXPECT_EQ(back.base_position_W, state.base_position_W);
  EXPECT_NEAR(back.base_orientation_W.angularDistance(state.base_orientation_W), 0.0, 1e-12);
  EXPECT_EQ(back.base_linear_velocity_W, state.base_linear_velocity_W);
  EXPECT_EQ(back.base_angular_velocity_B, state.base_angular_velocity_B);
  EXPECT_EQ(back.q, state.q);
  EXPECT_EQ(back.qd, state.qd);
  EXPECT_EQ(back.tau, state.tau);
  EXPECT_EQ(back.foot_contact, state.foot_contact);
  EXPECT_EQ(back.foot_force_W[2], state.foot_force_W[2]);

  auto bad = ToRobotStateMsg(state);
  bad.joint_velocity[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(FromRobotStateMsg(bad), InputError);
  bad = ToRobotStateMsg(state);
  bad.base_orientation[0] = 2.0;
  EXPECT_THROW(FromRobotStateMsg(bad), InputError);
}

TEST(Convert, ControllerStatusRoundTripAndValidation) {
  ControllerProgress walking;
  walking.plan_seq = 4;
  walking.steps_done = 17;
  walking.phase = "swing";
  walking.step = 3;
  walking.swing_leg = 2;
  walking.base_error_m = 0.004;
  walking.step_max_base_error_m = 0.009;
  walking.support_margin_m = 0.05;
  walking.steps_committed = 2;
  walking.lag_s = 0.25;
  const auto msg = ToControllerStatusMsg(2000000, walking);
  EXPECT_FALSE(msg.awaiting_plan);
  ControllerProgress back = FromControllerStatusMsg(msg);
  EXPECT_EQ(back.plan_seq, 4);
  EXPECT_EQ(back.steps_done, 17);
  EXPECT_FALSE(back.awaiting_since.has_value());
  EXPECT_EQ(back.phase, "swing");
  EXPECT_EQ(back.step, 3);
  EXPECT_EQ(back.swing_leg, 2);
  EXPECT_EQ(back.base_error_m, 0.004);
  EXPECT_EQ(back.step_max_base_error_m, 0.009);
  EXPECT_EQ(back.support_margin_m, 0.05);
  EXPECT_EQ(back.steps_committed, 2);
  EXPECT_EQ(back.lag_s, 0.25);

  ControllerProgress at_boundary = walking;
  at_boundary.awaiting_since = 1990000;
  auto waiting = ToControllerStatusMsg(2000000, at_boundary);
  EXPECT_TRUE(waiting.awaiting_plan);
  back = FromControllerStatusMsg(waiting);
  ASSERT_TRUE(back.awaiting_since.has_value());
  EXPECT_EQ(*back.awaiting_since, 1990000);

  auto bad = waiting;
  bad.awaiting_since = waiting.utime + 1;  // a wait that begins after the status
  EXPECT_THROW(FromControllerStatusMsg(bad), InputError);
  bad = waiting;
  bad.steps_done = -1;
  EXPECT_THROW(FromControllerStatusMsg(bad), InputError);
  bad = waiting;
  bad.swing_leg = 4;
  EXPECT_THROW(FromControllerStatusMsg(bad), InputError);
  bad = waiting;
  bad.base_error = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(FromControllerStatusMsg(bad), InputError);
  bad = waiting;
  bad.phase = std::string(100, 'x');
  EXPECT_THROW(FromControllerStatusMsg(bad), InputError);
  bad = waiting;
  bad.steps_committed = -1;
  EXPECT_THROW(FromControllerStatusMsg(bad), InputError);
  bad = waiting;
  bad.lag_s = std::numeric_limits<double>::infinity();
  EXPECT_THROW(FromControllerStatusMsg(bad), InputError);
}

TEST(Convert, APlanStateCarriesItsSwing) {
  ContactPlan plan;
  plan.states.resize(2);
  plan.states[1].moving_leg = 1;
  plan.states[1].base_position = Eigen::Vector3d(0, 0, 0.45);
  plan.states[1].swing_apex_z = 0.12;
  plan.states[1].swing_bow = Eigen::Vector2d(0.03, -0.01);
  const ContactPlan back = FromContactPlanMsg(ToContactPlanMsg(plan, 1, 1, 5));
  EXPECT_FALSE(back.states[0].HasSwing());
  ASSERT_TRUE(back.states[1].HasSwing());
  EXPECT_EQ(back.states[1].swing_apex_z, 0.12);
  EXPECT_EQ(back.states[1].swing_bow, Eigen::Vector2d(0.03, -0.01));
  auto msg = ToContactPlanMsg(plan, 1, 1, 5);
  msg.states[1].swing_apex_z = 30.0;  // far above the base
  EXPECT_THROW(FromContactPlanMsg(msg), InputError);
  msg = ToContactPlanMsg(plan, 1, 1, 5);
  msg.states[1].swing_bow[0] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(FromContactPlanMsg(msg), InputError);
  msg = ToContactPlanMsg(plan, 1, 1, 5);
  msg.states[0].swing_apex_z = 0.1;  // the first state has no swing
  EXPECT_THROW(FromContactPlanMsg(msg), InputError);
}

TEST(Convert, APlanStateCarriesItsTiming) {
  ContactPlan plan;
  plan.states.resize(3);
  for (int i = 1; i <= 2; ++i) {
    plan.states[static_cast<std::size_t>(i)].moving_leg = i;
    plan.states[static_cast<std::size_t>(i)].lift_off_s = 0.6 * i;
    plan.states[static_cast<std::size_t>(i)].touch_down_s = 0.6 * i + 0.4;
  }
  const ContactPlan back = FromContactPlanMsg(ToContactPlanMsg(plan, 1, 1, 5));
  ASSERT_TRUE(back.Timed());
  EXPECT_EQ(back.states[2].lift_off_s, 1.2);
  EXPECT_EQ(back.states[2].touch_down_s, 1.6);
  EXPECT_TRUE(std::isnan(back.states[0].lift_off_s));
  auto msg = ToContactPlanMsg(plan, 1, 1, 5);
  msg.states[2].lift_off_s = 0.9;  // before the previous touch-down
  EXPECT_THROW(FromContactPlanMsg(msg), InputError);
  msg = ToContactPlanMsg(plan, 1, 1, 5);
  msg.states[1].touch_down_s = std::numeric_limits<double>::quiet_NaN();  // half timed
  EXPECT_THROW(FromContactPlanMsg(msg), InputError);
  msg = ToContactPlanMsg(plan, 1, 1, 5);
  msg.states[2].lift_off_s = msg.states[2].touch_down_s = std::numeric_limits<double>::quiet_NaN();  // one step untimed
  EXPECT_THROW(FromContactPlanMsg(msg), InputError);
  msg = ToContactPlanMsg(plan, 1, 1, 5);
  msg.states[0].lift_off_s = 0.0;  // the first state is where the plan starts
  EXPECT_THROW(FromContactPlanMsg(msg), InputError);
  plan.ClearTiming();
  EXPECT_FALSE(FromContactPlanMsg(ToContactPlanMsg(plan, 1, 1, 5)).Timed());
}

TEST(Convert, AffordanceRoundTripAndValidation) {
  AffordanceSurface s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  s.normal = {0, 0, 1};
  s.area = 0.5;
  const auto msg = ToAffordanceMsg({s, s}, 7, 5);
  EXPECT_EQ(msg.num_surfaces, 2);
  EXPECT_EQ(msg.surfaces[1].id, 1);
  const auto back = FromAffordanceMsg(msg);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].vertices[2], s.vertices[2]);
  EXPECT_EQ(back[0].normal, s.normal);
  EXPECT_DOUBLE_EQ(back[0].area, 0.5);

  auto bad = msg;
  bad.surfaces[0].area = std::numeric_limits<double>::infinity();
  EXPECT_THROW(FromAffordanceMsg(bad), InputError);
  bad = msg;
  bad.surfaces[1].num_vertices = 2;
  bad.surfaces[1].vertices.resize(2);
  EXPECT_THROW(FromAffordanceMsg(bad), InputError);
}

/// The InputError `convert` throws, "" if it throws none.
template <typename Convert>
std::string ProblemOf(Convert&& convert) {
  try {
    convert();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string AffordanceProblem(const rbcp_msgs::affordance_set_t& msg) {
  return ProblemOf([&] { FromAffordanceMsg(msg); });
}

TEST(Convert, SurfacesNeedUnitNormalsSaneVerticesAndAreas) {
  AffordanceSurface s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  s.normal = {0, 0, 1};
  s.area = 0.5;
  const auto msg = ToAffordanceMsg({s}, 7, 5);
  EXPECT_EQ(AffordanceProblem(msg), "");
  auto nearly = msg;
  nearly.surfaces[0].normal[2] = 1.0005;  // within the tolerance: made exactly unit
  EXPECT_DOUBLE_EQ(FromAffordanceMsg(nearly)[0].normal.norm(), 1.0);
  auto bad = msg;
  for (double& n : bad.surfaces[0].normal) n = 0.0;
  EXPECT_EQ(AffordanceProblem(bad), "affordance surface 0: expected a unit normal, got (0, 0, 0) of norm 0.000000");
  bad.surfaces[0].normal[2] = 2.0;
  EXPECT_EQ(AffordanceProblem(bad), "affordance surface 0: expected a unit normal, got (0, 0, 2) of norm 2.000000");
  bad = msg;
  bad.surfaces[0].vertices[1][0] = 1e9;
  EXPECT_EQ(AffordanceProblem(bad), "affordance surface 0: vertex 1 (1e+09, 0, 0) is beyond 100000 m of the origin");
  bad = msg;
  bad.surfaces[0].area = -1.0;
  EXPECT_EQ(AffordanceProblem(bad), "affordance surface 0: expected an area >= 0, got -1.000000");
}

TEST(Convert, TerrainAndRobotStateBeyondSaneExtentsAreRejected) {
  auto terrain = ToTerrainMsg(MakeBoxMesh({1, 1, 1}), 0, "");
  terrain.vertices[3][2] = -2e5;
  const std::string problem = ProblemOf([&] { FromTerrainMsg(terrain); });
  EXPECT_EQ(problem.rfind("terrain mesh: vertex 3 (", 0), 0u) << problem;
  EXPECT_NE(problem.find(") is beyond 100000 m of the origin"), std::string::npos) << problem;
  RobotState state;
  auto msg = ToRobotStateMsg(state);
  msg.base_position[1] = 1e300;
  EXPECT_THROW(FromRobotStateMsg(msg), InputError);
}

rbcp_msgs::root_path_t StraightPath(int n, double dt) {
  rbcp_msgs::root_path_t msg{};
  msg.num_points = n;
  for (int i = 0; i < n; ++i) {
    rbcp_msgs::root_path_point_t p{};
    p.t = i * dt;
    p.position[0] = 0.01 * i;
    p.position[2] = 0.45;
    p.orientation[0] = 1.0;
    msg.points.push_back(p);
  }
  return msg;
}

std::string RootPathProblem(const rbcp_msgs::root_path_t& msg, double max_duration_s) {
  return ProblemOf([&] { FromRootPathMsg(msg, max_duration_s); });
}

TEST(Convert, RootPathsAreValidatedAndTheirDurationCapped) {
  const auto msg = StraightPath(4, 0.5);
  const auto samples = FromRootPathMsg(msg, 10.0);
  ASSERT_EQ(samples.size(), 4u);
  EXPECT_DOUBLE_EQ(samples[3].t, 1.5);
  EXPECT_DOUBLE_EQ(samples[3].p.x(), 0.03);
  EXPECT_DOUBLE_EQ(samples[3].yaw, 0.0);

  EXPECT_EQ(RootPathProblem(StraightPath(4, 1e9), 3600.0),
            "root path: lasts 3000000000.000000 s, more than the limit of 3600 s");
  auto bad = msg;
  bad.points[2].t = bad.points[1].t;
  EXPECT_EQ(RootPathProblem(bad, 10.0), "root path: point 2: times must increase, got t = 0.500000 s after 0.500000 s");
  bad = msg;
  bad.points[1].orientation[0] = 0.0;
  EXPECT_EQ(RootPathProblem(bad, 10.0), "root path: point 1: orientation is not a unit quaternion");
  bad = msg;
  bad.points[0].position[1] = -1e6;
  EXPECT_EQ(RootPathProblem(bad, 10.0),
            "root path: point 0: position (0, -1e+06, 0.45) is beyond 100000 m of the origin");
  bad = msg;
  bad.num_points = 5;
  EXPECT_EQ(RootPathProblem(bad, 10.0), "root path: count 5 disagrees with 4 points");
  EXPECT_EQ(RootPathProblem(StraightPath(0, 1.0), 10.0), "root path: no point");
}

std::string Problem(const std::optional<PlanRequestProblem>& problem) { return problem ? problem->Describe() : "none"; }

TEST(Convert, PlanRequestsAreValidatedAndTheirBudgetCapped) {
  rbcp_msgs::plan_request_t r{};
  r.goal_position[0] = 2.0;
  r.time_budget = 5.0;
  EXPECT_EQ(Problem(CheckPlanRequest(r, 60.0)), "none");
  r.time_budget = 1e9;
  EXPECT_EQ(Problem(CheckPlanRequest(r, 60.0)), "plan request: time_budget 1000000000.000000 s exceeds the limit of 60 s");
  r.time_budget = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Problem(CheckPlanRequest(r, 60.0)), "plan request: time_budget is not finite");
  r.time_budget = 0.0;  // the planner's default
  r.goal_position[1] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(Problem(CheckPlanRequest(r, 60.0)), "plan request: goal is not finite");
  EXPECT_EQ(CheckPlanRequest(r, 60.0)->kind, PlanRequestProblem::Kind::kGoal);
  r.goal_position[1] = 0.0;
  r.start_position[0] = 5e5;
  EXPECT_EQ(Problem(CheckPlanRequest(r, 60.0)), "none") << "the start is ignored without use_start";
  r.use_start = true;
  EXPECT_EQ(Problem(CheckPlanRequest(r, 60.0)), "plan request: start (500000, 0, 0) is beyond 100000 m of the origin");
}

TEST(Convert, ContactPlanRoundTripAndValidation) {
  ContactPlan plan;
  for (int i = 0; i < 3; ++i) {
    WholeBodyState s;
    s.base_position = {0.1 * i, 0.0, 0.45};
    s.base_rpy = {0.0, 0.01, 0.2};
    for (int j = 0; j < 12; ++j) s.joints[j] = 0.01 * j + i;
    for (int leg = 0; leg < kNumLegs; ++leg) s.feet[static_cast<std::size_t>(leg)].position = {leg + 0.5, i * 1.0, 0.0};
    s.moving_leg = i - 1;
    plan.states.push_back(s);
  }
  plan.reaches_goal = false;
  const auto msg = ToContactPlanMsg(plan, 11, 3, 77, 42, 9000);
  EXPECT_EQ(msg.request_id, 3);
  EXPECT_EQ(msg.terrain_id, 77);
  EXPECT_EQ(msg.plan_seq, 42);
  EXPECT_EQ(msg.start_utime, 9000);
  EXPECT_FALSE(msg.reaches_goal);
  const ContactPlan back = FromContactPlanMsg(msg);
  EXPECT_FALSE(back.reaches_goal);
  ASSERT_EQ(back.states.size(), 3u);
  EXPECT_EQ(back.states[2].joints, plan.states[2].joints);
  EXPECT_EQ(back.states[1].feet[3].position, plan.states[1].feet[3].position);
  EXPECT_EQ(back.states[0].moving_leg, -1);
  EXPECT_EQ(back.states[2].moving_leg, 1);

  auto bad = msg;
  bad.states[1].moving_leg = 4;
  EXPECT_THROW(FromContactPlanMsg(bad), InputError);
  bad = msg;
  bad.states[0].joint_position[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(FromContactPlanMsg(bad), InputError);
}

TEST(Convert, ATerrainsIdIsItsContentAndIsChecked) {
  const TriangleMesh box = MakeBoxMesh({1.0, 2.0, 0.5});
  TriangleMesh moved = box;
  moved.vertices[5].z() += 1e-9;
  TriangleMesh rewound = box;
  std::swap(rewound.triangles[0][1], rewound.triangles[0][2]);
  EXPECT_NE(TerrainId(box), 0);
  EXPECT_EQ(TerrainId(box), TerrainId(MakeBoxMesh({1.0, 2.0, 0.5})));  // whoever makes it, whenever
  EXPECT_NE(TerrainId(box), TerrainId(moved));
  EXPECT_NE(TerrainId(box), TerrainId(rewound));
  EXPECT_NE(TerrainId(box), TerrainId(MakeBoxMesh({1.0, 2.0, 0.6})));
  // A message whose id is not its content's is rejected: an id names one terrain only.
  auto msg = ToTerrainMsg(box, 1, "box");
  msg.vertices[5][2] += 1e-9;
  const std::string problem = ProblemOf([&] { FromTerrainMsg(msg); });
  EXPECT_NE(problem.find("terrain_id " + std::to_string(TerrainId(box)) + " is not its content's"), std::string::npos)
      << problem;
  msg.terrain_id = TerrainId(moved);
  EXPECT_EQ(ProblemOf([&] { FromTerrainMsg(msg); }), "");
}

}  // namespace
}  // namespace rbcp::transport
