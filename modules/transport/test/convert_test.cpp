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

TEST(Convert, ControllerProgressRidesWithTheRobotState) {
  RobotState state;
  state.t = 2.0;
  const auto walking = ToRobotStateMsg(state, ControllerProgress{4, 17, std::nullopt});
  EXPECT_FALSE(walking.awaiting_plan);
  ControllerProgress back = ProgressFromRobotStateMsg(walking);
  EXPECT_EQ(back.plan_seq, 4);
  EXPECT_EQ(back.steps_done, 17);
  EXPECT_FALSE(back.awaiting_since.has_value());

  auto waiting = ToRobotStateMsg(state, ControllerProgress{4, 18, 1990000});
  EXPECT_TRUE(waiting.awaiting_plan);
  back = ProgressFromRobotStateMsg(waiting);
  ASSERT_TRUE(back.awaiting_since.has_value());
  EXPECT_EQ(*back.awaiting_since, 1990000);

  waiting.awaiting_since = waiting.utime + 1;  // a wait that begins after the state
  EXPECT_THROW(ProgressFromRobotStateMsg(waiting), InputError);
  waiting.awaiting_since = 0;
  waiting.steps_done = -1;
  EXPECT_THROW(ProgressFromRobotStateMsg(waiting), InputError);
}

TEST(Convert, AffordanceRoundTripAndValidation) {
  AffordanceSurface s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  s.normal = {0, 0, 1};
  s.area = 0.5;
  const auto msg = ToAffordanceMsg({s, s}, 7);
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
  const auto msg = ToContactPlanMsg(plan, 11, 3, 42, 9000);
  EXPECT_EQ(msg.request_id, 3);
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

}  // namespace
}  // namespace rbcp::transport
