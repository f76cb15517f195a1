#include "rbcp/nodes/root_planner_node.h"

#include <gtest/gtest.h>

#include <limits>
#include <optional>

#include "rbcp/core/yaml_reader.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/transport/convert.h"
#include "rbcp_msgs/process_status_t.hpp"
#include "world_messages.h"

namespace rbcp::nodes {
namespace {

const std::string kConfig = std::string(RBCP_SOURCE_DIR) + "/config";

class RootPlannerNodeTest : public ::testing::Test {
 protected:
  void SetUp() override { node_.status().set_verbose(false); }
  void Pump() {
    while (lcm_.handleTimeout(0) > 0) {
    }
  }
  void PublishWorld(const std::string& scenario_name) {
    test::PublishWorld(lcm_, LoadScenario(kConfig + "/scenarios/" + scenario_name + ".yaml"), kConfig);
  }
  static rbcp_msgs::plan_request_t Request(double sx, double gx, int64_t id) {
    rbcp_msgs::plan_request_t r{};
    r.utime = 200;
    r.request_id = id;
    r.use_start = true;
    r.start_position[0] = sx;
    r.goal_position[0] = gx;
    r.time_budget = 5.0;
    r.seed = 3;
    return r;
  }

  /// The robot's measured state at utime 300, level and facing +x, its base at (x, 0, z).
  static rbcp_msgs::robot_state_t StandingAt(double x, double z) {
    rbcp_msgs::robot_state_t state{};
    state.utime = 300;
    state.base_position[0] = x;
    state.base_position[2] = z;
    state.base_orientation[0] = 1.0;
    return state;
  }

  /// The robot's measured state, and its controller's status at the same time.
  struct Robot {
    rbcp_msgs::robot_state_t state{};
    rbcp_msgs::controller_status_t controller{};
  };
  void Publish(const Robot& robot) {
    lcm_.publish(channels::kControllerStatus, &robot.controller);
    lcm_.publish(channels::kRobotState, &robot.state);
  }

  /// The contact planner's first FAILED answer (no foothold) to the wait at `input_utime`.
  static rbcp_msgs::process_status_t ContactPlannerFailed(int64_t input_utime) {
    rbcp_msgs::process_status_t failed{};
    failed.process = "contact_planner";
    failed.pid = 77;
    failed.state = rbcp_msgs::process_status_t::FAILED;
    failed.reason = "no_foothold: no valid step for LF at path time 3.10 s";
    failed.input_utime = input_utime;
    failed.handled = 1;
    return failed;
  }

  /// Publishes `state` (or `robot`), steps the node (expecting it to plan) and returns the
  /// ROOT_PATH, if any.
  std::optional<rbcp_msgs::root_path_t> PathAfter(const rbcp_msgs::robot_state_t& state) {
    lcm_.publish(channels::kRobotState, &state);
    return PathNow();
  }
  std::optional<rbcp_msgs::root_path_t> PathAfter(const Robot& robot) {
    Publish(robot);
    return PathNow();
  }
  std::optional<rbcp_msgs::root_path_t> PathNow() {
    Pump();
    EXPECT_TRUE(node_.Step());
    Pump();
    auto path = path_.Take();
    if (!path && status_.Latest()) ADD_FAILURE() << status_.Latest()->reason;
    return path;
  }

  /// Steps the node expecting it to answer that the pending request waits (ALIVE, once), and
  /// returns what it waits for.
  std::string WaitingFor() {
    Pump();
    EXPECT_TRUE(node_.Step()) << "a waiting request is told so";
    Pump();
    EXPECT_FALSE(node_.Step()) << "once";
    EXPECT_FALSE(path_.Take().has_value());
    if (!status_.Latest()) return "";
    EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::ALIVE);
    return status_.Latest()->reason;
  }

  lcm::LCM lcm_{"memq://"};
  RobotModel robot_ = RobotModel::LoadDefault(kConfig);
  RootPlannerNode node_{lcm_, robot_, RootPlannerConfig::LoadFile(kConfig + "/root_planner.yaml", kConfig)};
  transport::LatestMessage<rbcp_msgs::root_path_t> path_{lcm_, channels::kRootPath};
  transport::LatestMessage<rbcp_msgs::process_status_t> status_{lcm_, channels::kStatus};
};

TEST_F(RootPlannerNodeTest, WaitsForTheWorldThenPlansAndPublishes) {
  const auto request = Request(0.0, 1.5, 7);
  lcm_.publish(channels::kPlanRequest, &request);
  EXPECT_EQ(WaitingFor(), "waiting for TERRAIN and AFFORDANCES") << "no terrain yet: the request stays pending";
  PublishWorld("flat_ground");
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  auto path = path_.Take();
  ASSERT_TRUE(path.has_value()) << status_.Latest()->reason;
  EXPECT_EQ(path->request_id, 7);
  ASSERT_GT(path->num_points, 2);
  EXPECT_NEAR(path->points.front().position[0], 0.0, 1e-9);
  EXPECT_NEAR(path->points.back().position[0], 1.5, 1e-9);
  EXPECT_NEAR(path->points.back().position[2], robot_.NominalBaseHeight(), 1e-9);
  for (int i = 1; i < path->num_points; ++i) EXPECT_GT(path->points[i].t, path->points[i - 1].t);
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
  EXPECT_FALSE(node_.Step()) << "a request is answered once";
}

TEST_F(RootPlannerNodeTest, ReplansFromTheMeasuredRobotState) {
  PublishWorld("flat_ground");
  auto request = Request(0.0, 1.5, 8);
  request.use_start = false;
  lcm_.publish(channels::kPlanRequest, &request);
  EXPECT_EQ(WaitingFor(), "waiting for ROBOT_STATE: the request starts where the robot stands");
  auto state = StandingAt(0.5, 0.45);
  const auto path = PathAfter(state);
  ASSERT_TRUE(path.has_value());
  EXPECT_NEAR(path->points.front().position[0], 0.5, 1e-9);
  EXPECT_EQ(path->utime, 300);
}

TEST_F(RootPlannerNodeTest, AMeasuredBaseInsideABoxFailsInsteadOfStandingOnItsTop) {
  // flat_ground with a 0.8 m box where the robot stands.
  test::PublishWorld(lcm_, ParseScenario(R"(name: box_on_robot
terrain:
  - box: {size: [8.5, 3, 0.5], position: [2.5, 0, -0.25], rpy: [0, 0, 0]}
  - box: {size: [1, 1, 0.8], position: [0.5, 0, 0.4], rpy: [0, 0, 0]}
start: {position: [0, 0], yaw: 0}
goal: {position: [3, 0], yaw: 0}
)",
                                                 ""),
                     kConfig);
  auto request = Request(0.0, 3.0, 9);
  request.use_start = false;
  lcm_.publish(channels::kPlanRequest, &request);
  auto state = StandingAt(0.5, 0.45);
  lcm_.publish(channels::kRobotState, &state);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_FALSE(path_.Take().has_value()) << "no path from the top of the box";
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(status_.Latest()->reason,
            "start_invalid: the measured base at (0.50, 0.00, 0.45) is inside the terrain, which rises to z 0.80 there");
  // Standing beside the box, the same request is planned.
  state.utime = 400;
  state.base_position[0] = -0.5;
  auto again = Request(0.0, 3.0, 10);
  again.use_start = false;
  lcm_.publish(channels::kPlanRequest, &again);
  EXPECT_TRUE(PathAfter(state).has_value());
}

TEST_F(RootPlannerNodeTest, PlansFromTheHeightTheRobotStandsAtAcrossAStepEdge) {
  // A 0.2 m step from x = 0.5; the base just over its edge with the fore feet on it and the hind
  // feet on the floor 0.45 m behind, half way up. At the step's top plus the nominal height the
  // hind legs would not reach the floor.
  test::PublishWorld(lcm_, ParseScenario(R"(name: step_edge
terrain:
  - box: {size: [3, 3, 0.5], position: [-1.0, 0, -0.25], rpy: [0, 0, 0]}
  - box: {size: [3, 3, 0.7], position: [2.0, 0, -0.15], rpy: [0, 0, 0]}
start: {position: [-1, 0], yaw: 0}
goal: {position: [2, 0], yaw: 0}
)",
                                                 ""),
                     kConfig);
  auto request = Request(0.0, 2.0, 11);
  request.use_start = false;
  lcm_.publish(channels::kPlanRequest, &request);
  auto state = StandingAt(0.55, 0.1 + robot_.NominalBaseHeight());
  const auto path = PathAfter(state);
  ASSERT_TRUE(path.has_value());
  EXPECT_NEAR(path->points.front().position[0], 0.55, 1e-9);
  // At the measured height, or raised a few centimetres where the trunk would touch the edge.
  EXPECT_GE(path->points.front().position[2], state.base_position[2] - 1e-9);
  EXPECT_LE(path->points.front().position[2], state.base_position[2] + 0.05 + 1e-9);
}

TEST_F(RootPlannerNodeTest, ReplansWhenTheRobotLeavesThePathOrTheTerrainChanges) {
  PublishWorld("flat_ground");
  const auto request = Request(0.0, 1.5, 9);
  lcm_.publish(channels::kPlanRequest, &request);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  ASSERT_TRUE(path_.Take().has_value()) << status_.Latest()->reason;

  const auto waiting = [](int64_t utime, double x, double y) {
    Robot robot;
    robot.state.utime = utime;
    robot.state.base_position[0] = x;
    robot.state.base_position[1] = y;
    robot.state.base_position[2] = 0.45;
    robot.state.base_orientation[0] = 1.0;
    robot.controller.utime = utime;
    robot.controller.awaiting_plan = true;
    robot.controller.awaiting_since = utime;
    return robot;
  };
  // Waiting on the path: no new path; the same world again is no change either.
  Publish(waiting(1000000, 0.4, 0.05));
  PublishWorld("flat_ground");
  Pump();
  EXPECT_FALSE(node_.Step());
  EXPECT_FALSE(path_.Take().has_value());

  // Waiting 0.4 m beside it (pushed): a new path from there, for the same request.
  auto path = PathAfter(waiting(2000000, 0.5, 0.4));
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->request_id, 9);
  EXPECT_NEAR(path->points.front().position[0], 0.5, 1e-9);
  EXPECT_NEAR(path->points.front().position[1], 0.4, 1e-9);
  EXPECT_NE(status_.Latest()->reason.find("0.40 m from the path"), std::string::npos) << status_.Latest()->reason;
  EXPECT_FALSE(node_.Step()) << "one wait, one check";

  // A changed terrain (a shorter floor): planned again from the measured base.
  test::PublishWorld(lcm_, LoadScenario(std::string(RBCP_SOURCE_DIR) + "/tests/data/flat_short.yaml"), kConfig);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  path = path_.Take();
  ASSERT_TRUE(path.has_value()) << status_.Latest()->reason;
  EXPECT_NE(status_.Latest()->reason.find("the terrain changed"), std::string::npos) << status_.Latest()->reason;

  // The terrain changes while the robot walks: the new path starts where it next waits.
  auto walking = waiting(3000000, 0.6, 0.0);
  walking.controller.awaiting_plan = false;
  Publish(walking);
  PublishWorld("flat_ground");
  Pump();
  EXPECT_FALSE(node_.Step());
  EXPECT_FALSE(path_.Take().has_value()) << "no replan in the middle of a step";
  path = PathAfter(waiting(3500000, 0.7, 0.0));
  ASSERT_TRUE(path.has_value());
  EXPECT_NEAR(path->points.front().position[0], 0.7, 1e-9);
  EXPECT_NE(status_.Latest()->reason.find("the terrain changed"), std::string::npos) << status_.Latest()->reason;
}

TEST_F(RootPlannerNodeTest, AReplanThatFailsLeavesTheRobotThePathItFollows) {
  PublishWorld("flat_ground");
  const auto request = Request(0.0, 1.5, 12);
  lcm_.publish(channels::kPlanRequest, &request);
  const auto first = PathNow();
  ASSERT_TRUE(first.has_value());

  // The robot waits 0.4 m beside the path with its base measured inside the floor: no new path
  // from there, and the path it follows stays the request's.
  Robot robot;
  robot.state.utime = robot.controller.utime = robot.controller.awaiting_since = 1000000;
  robot.state.base_position[0] = 0.5;
  robot.state.base_position[1] = 0.4;
  robot.state.base_position[2] = -0.2;
  robot.state.base_orientation[0] = 1.0;
  robot.controller.awaiting_plan = true;
  Publish(robot);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_FALSE(path_.Take().has_value());
  ASSERT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(status_.Latest()->reason.find("start_invalid"), std::string::npos) << status_.Latest()->reason;
  EXPECT_NE(status_.Latest()->reason.find("the robot goes on along the previous path"), std::string::npos)
      << status_.Latest()->reason;
  auto repeat = request;  // the operator's repeat is answered with that path
  repeat.utime = 900;
  lcm_.publish(channels::kPlanRequest, &repeat);
  const auto kept = PathNow();
  ASSERT_TRUE(kept.has_value());
  EXPECT_EQ(kept->utime, first->utime);
  EXPECT_EQ(kept->num_points, first->num_points);

  // At its next wait, standing 0.4 m beside the path, the robot gets a new one from there.
  robot.state.utime = robot.controller.utime = robot.controller.awaiting_since = 2000000;
  robot.state.base_position[2] = 0.45;
  const auto path = PathAfter(robot);
  ASSERT_TRUE(path.has_value());
  EXPECT_NEAR(path->points.front().position[1], 0.4, 1e-9);

  // A new request that fails leaves no path: its repeat gets the failure again.
  const auto off_terrain = Request(0.0, 40.0, 13);
  lcm_.publish(channels::kPlanRequest, &off_terrain);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(status_.Latest()->reason.find("previous path"), std::string::npos) << status_.Latest()->reason;
}

TEST_F(RootPlannerNodeTest, PlansTheNextGuideWhenNoContactPlanFollowsThePath) {
  PublishWorld("flat_ground");
  const auto request = Request(0.0, 1.5, 4);
  lcm_.publish(channels::kPlanRequest, &request);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  ASSERT_TRUE(path_.Take().has_value()) << status_.Latest()->reason;

  Robot robot;
  robot.state.utime = 1000000;
  robot.state.base_position[0] = 0.3;
  robot.state.base_position[2] = 0.45;
  robot.state.base_orientation[0] = 1.0;
  robot.controller.utime = robot.state.utime;
  robot.controller.awaiting_plan = true;
  robot.controller.awaiting_since = robot.state.utime;
  robot.controller.steps_done = 1;  // it has walked
  Publish(robot);
  Pump();
  EXPECT_FALSE(node_.Step()) << "the robot waits on the path";

  rbcp_msgs::process_status_t failed = ContactPlannerFailed(robot.state.utime);
  const auto contact_planner_says = [&](int64_t handled, const std::string& reason) {
    failed.handled = handled;
    failed.reason = reason;
    lcm_.publish(channels::kStatus, &failed);
  };
  contact_planner_says(1, "no_foothold: no valid step for LF at path time 3.10 s");
  auto path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->request_id, 4);
  EXPECT_NEAR(path->points.front().position[0], 0.3, 1e-9) << "from where the robot stands";
  EXPECT_NE(status_.Latest()->reason.find("guide 2"), std::string::npos) << status_.Latest()->reason;

  // The same failure again (a heartbeat) and a rejected input are no new planning failure.
  contact_planner_says(1, "no_foothold: no valid step for LF at path time 3.10 s");
  Pump();
  EXPECT_FALSE(node_.Step());
  contact_planner_says(2, "cannot decode ROOT_PATH (12 bytes): truncated");
  Pump();
  EXPECT_FALSE(node_.Step());

  // Out of budget along the second guide: the third; then guide_retries (2) are spent for this wait.
  contact_planner_says(3, "timeout: time budget of 10.00 s exhausted");
  path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_NE(status_.Latest()->reason.find("guide 3"), std::string::npos) << status_.Latest()->reason;
  contact_planner_says(4, "no_foothold: no valid step for RH at path time 0.40 s");
  Pump();
  EXPECT_FALSE(node_.Step());
  EXPECT_FALSE(path_.Take().has_value());

  // Asked again in the same stance: no more guides. After a step, a failure gets the next guide.
  robot.state.utime = robot.controller.utime = robot.controller.awaiting_since = 1500000;
  Publish(robot);
  failed.input_utime = robot.state.utime;
  contact_planner_says(5, "no_foothold: no valid step for RH at path time 0.40 s");
  Pump();
  EXPECT_FALSE(node_.Step());
  robot.state.utime = robot.controller.utime = robot.controller.awaiting_since = 2000000;
  robot.controller.steps_done = 2;
  Publish(robot);
  failed.input_utime = robot.state.utime;
  contact_planner_says(6, "no_foothold: no valid step for RH at path time 0.40 s");
  path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_NE(status_.Latest()->reason.find("guide 4"), std::string::npos) << status_.Latest()->reason;
}

TEST_F(RootPlannerNodeTest, BeforeTheFirstStepTheNextGuideStartsAtTheRequestsStart) {
  PublishWorld("flat_ground");
  const auto request = Request(0.0, 1.5, 5);
  lcm_.publish(channels::kPlanRequest, &request);
  ASSERT_TRUE(PathNow().has_value());
  // The robot stands 4 cm beside the start, no step taken, and no contact plan follows the path.
  Robot robot;
  robot.state.utime = robot.controller.utime = robot.controller.awaiting_since = 1000000;
  robot.state.base_position[1] = 0.04;
  robot.state.base_position[2] = 0.45;
  robot.state.base_orientation[0] = 1.0;
  robot.controller.awaiting_plan = true;
  Publish(robot);
  const rbcp_msgs::process_status_t failed = ContactPlannerFailed(robot.state.utime);
  lcm_.publish(channels::kStatus, &failed);
  const auto path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_NE(status_.Latest()->reason.find("guide 2"), std::string::npos) << status_.Latest()->reason;
  EXPECT_NEAR(path->points.front().position[1], 0.0, 1e-9) << "from the request's start, as offline";
}

TEST_F(RootPlannerNodeTest, BadRequestsFailWithAReason) {
  PublishWorld("flat_ground");
  auto request = Request(0.0, 1.5, 9);
  request.goal_position[1] = std::numeric_limits<double>::quiet_NaN();
  lcm_.publish(channels::kPlanRequest, &request);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(status_.Latest()->reason, "plan request: goal is not finite");

  request = Request(0.0, 40.0, 10);  // far beyond the floor
  lcm_.publish(channels::kPlanRequest, &request);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(status_.Latest()->reason, "no terrain under the goal");
  EXPECT_FALSE(path_.Take().has_value());
}

TEST_F(RootPlannerNodeTest, SurfacesWithoutUnitNormalsFailAndTheNextValidWorldIsPlannedOn) {
  const Scenario scenario = LoadScenario(kConfig + "/scenarios/flat_ground.yaml");
  const auto surfaces = AffordanceExtractor(AffordanceConfig::Load(YamlMap::LoadFile(kConfig + "/affordance.yaml")))
                            .Extract(scenario.terrain_mesh);
  const auto terrain = transport::ToTerrainMsg(scenario.terrain_mesh, 100, scenario.name);
  auto affordances = transport::ToAffordanceMsg(surfaces, 100, terrain.terrain_id);
  ASSERT_FALSE(affordances.surfaces.empty());
  for (double& n : affordances.surfaces[0].normal) n = 0.0;
  lcm_.publish(channels::kTerrain, &terrain);
  lcm_.publish(channels::kAffordances, &affordances);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(status_.Latest()->reason,
            "affordance surface 0: expected a unit normal, got (0, 0, 0) of norm 0.000000");

  const auto request = Request(0.0, 1.5, 11);
  lcm_.publish(channels::kPlanRequest, &request);
  EXPECT_EQ(WaitingFor(), "waiting for TERRAIN and AFFORDANCES") << "no valid surfaces: the request waits";

  affordances.surfaces[0].normal[2] = 1.0;
  lcm_.publish(channels::kAffordances, &affordances);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  ASSERT_TRUE(path_.Take().has_value()) << status_.Latest()->reason;
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
}

TEST_F(RootPlannerNodeTest, ATimeBudgetBeyondTheLimitIsRejected) {
  PublishWorld("flat_ground");
  auto request = Request(0.0, 1.5, 12);
  request.time_budget = 1e9;
  lcm_.publish(channels::kPlanRequest, &request);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(status_.Latest()->reason, "plan request: time_budget 1000000000.000000 s exceeds the limit of 60 s");
  EXPECT_FALSE(path_.Take().has_value());
}

TEST_F(RootPlannerNodeTest, ANewTerrainIsNeverPairedWithTheSurfacesOfTheOldOne) {
  PublishWorld("flat_ground");  // terrain and surfaces at utime 100
  Pump();
  EXPECT_FALSE(node_.Step());
  // A new terrain (another floor) whose surfaces have not come: the old surfaces are stale.
  const Scenario other = LoadScenario(kConfig + "/scenarios/plinth.yaml");
  const auto terrain = transport::ToTerrainMsg(other.terrain_mesh, 300, other.name);
  lcm_.publish(channels::kTerrain, &terrain);
  const auto request = Request(0.0, 1.5, 13);
  lcm_.publish(channels::kPlanRequest, &request);
  EXPECT_EQ(WaitingFor(), "waiting for TERRAIN and AFFORDANCES") << "the request waits for the new terrain's surfaces";
  // Surfaces of the old terrain, even sent at the new terrain's time, are not the new terrain's.
  const Scenario flat = LoadScenario(kConfig + "/scenarios/flat_ground.yaml");
  const auto stale = transport::ToAffordanceMsg({}, 300, transport::TerrainId(flat.terrain_mesh));
  lcm_.publish(channels::kAffordances, &stale);
  Pump();
  EXPECT_FALSE(node_.Step());
  // The new terrain's surfaces, even none at all, pair with it.
  const auto none = transport::ToAffordanceMsg({}, 300, terrain.terrain_id);
  lcm_.publish(channels::kAffordances, &none);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_FALSE(path_.Take().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(status_.Latest()->reason.find("no contact surfaces"), std::string::npos) << status_.Latest()->reason;
}

TEST_F(RootPlannerNodeTest, RequestIdsAreNotOrderedAndNoRequestShadowsAnother) {
  PublishWorld("flat_ground");
  const auto high = Request(0.0, 1.5, std::numeric_limits<int64_t>::max());
  lcm_.publish(channels::kPlanRequest, &high);
  auto path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->request_id, std::numeric_limits<int64_t>::max());
  // Another operator's run with a lower id is a new goal, not an old one.
  const auto low = Request(0.0, 1.0, 2);
  lcm_.publish(channels::kPlanRequest, &low);
  path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->request_id, 2);
  EXPECT_NEAR(path->points.back().position[0], 1.0, 1e-9);
  // The first operator still repeating its request (every second) does not take the goal back.
  lcm_.publish(channels::kPlanRequest, &high);
  Pump();
  EXPECT_FALSE(node_.Step());
  Pump();
  EXPECT_FALSE(path_.Take().has_value());
  // The same id for another goal is another request.
  const auto same_id_other_goal = Request(0.0, 1.25, 2);
  lcm_.publish(channels::kPlanRequest, &same_id_other_goal);
  path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_NEAR(path->points.back().position[0], 1.25, 1e-9);
}

TEST_F(RootPlannerNodeTest, ARepeatedRequestIsAnsweredAgain) {
  PublishWorld("flat_ground");
  const auto request = Request(0.0, 1.5, 21);
  lcm_.publish(channels::kPlanRequest, &request);
  const auto first = PathNow();
  ASSERT_TRUE(first.has_value());
  const int64_t handled = status_.Latest()->handled;
  auto repeat = request;
  repeat.utime = 900;  // the operator's repeat, later
  lcm_.publish(channels::kPlanRequest, &repeat);
  Pump();
  ASSERT_TRUE(node_.Step()) << "a repeat is answered";
  Pump();
  const auto again = path_.Take();
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->request_id, 21);
  ASSERT_EQ(again->num_points, first->num_points) << "the same path, not a new plan";
  EXPECT_EQ(again->points.back().position[0], first->points.back().position[0]);
  EXPECT_EQ(status_.Latest()->handled, handled);

  // A request that failed gets its failure again.
  const auto off_terrain = Request(0.0, 40.0, 22);
  lcm_.publish(channels::kPlanRequest, &off_terrain);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  ASSERT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  const std::string why = status_.Latest()->reason;
  const int64_t failures = status_.Latest()->handled;
  lcm_.publish(channels::kPlanRequest, &off_terrain);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(status_.Latest()->reason, why);
  EXPECT_EQ(status_.Latest()->handled, failures + 1) << "an answer, not a heartbeat";
  EXPECT_FALSE(path_.Take().has_value());
}

TEST_F(RootPlannerNodeTest, ARestartedClockDoesNotPairATerrainWithTheSurfacesOfAnother) {
  // An operator's run: the plinth, its surfaces, the clock at 5 s.
  test::PublishWorld(lcm_, LoadScenario(kConfig + "/scenarios/plinth.yaml"), kConfig, 5'000'000);
  Pump();
  EXPECT_FALSE(node_.Step());
  // The next run's world counts from 0 again: a flat floor whose surfaces have not come.
  const Scenario flat = LoadScenario(kConfig + "/scenarios/flat_ground.yaml");
  const auto terrain = transport::ToTerrainMsg(flat.terrain_mesh, 0, flat.name);
  lcm_.publish(channels::kTerrain, &terrain);
  const auto request = Request(0.0, 1.5, 31);
  lcm_.publish(channels::kPlanRequest, &request);
  EXPECT_EQ(WaitingFor(), "waiting for TERRAIN and AFFORDANCES") << "the plinth's surfaces are not the floor's";
  // The plinth's surfaces once more, late and later in time: still not the floor's.
  const auto plinth_surfaces = transport::ToAffordanceMsg(
      {}, 5'000'000, transport::TerrainId(LoadScenario(kConfig + "/scenarios/plinth.yaml").terrain_mesh));
  lcm_.publish(channels::kAffordances, &plinth_surfaces);
  Pump();
  EXPECT_FALSE(node_.Step());
  EXPECT_FALSE(path_.Take().has_value());
  // The floor's own surfaces, at its time.
  test::PublishWorld(lcm_, flat, kConfig, 0);
  const auto path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->request_id, 31);
  EXPECT_EQ(path->terrain_id, transport::TerrainId(flat.terrain_mesh)) << "the path names the terrain it was planned on";
}

TEST_F(RootPlannerNodeTest, AMessageWithAWrongTimeIsRejectedAndDoesNotStopTheClock) {
  PublishWorld("flat_ground");  // utime 100
  auto request = Request(0.0, 1.5, 41);
  request.utime = std::numeric_limits<int64_t>::max();
  lcm_.publish(channels::kPlanRequest, &request);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  ASSERT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(status_.Latest()->reason.find("PLAN_REQUEST: utime 9223372036854775807 us is not a simulated time"),
            std::string::npos)
      << status_.Latest()->reason;
  EXPECT_FALSE(path_.Take().has_value());
  // The next request, at the world's time, is planned and answered at that time.
  request.utime = 300;
  lcm_.publish(channels::kPlanRequest, &request);
  const auto path = PathNow();
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->utime, 300);
  EXPECT_EQ(status_.Latest()->utime, 300);
}

}  // namespace
}  // namespace rbcp::nodes

namespace rbcp::nodes {
namespace {

/// A floor from x = `begin_x` to `end_x`, `width` wide.
Scenario FloorFrom(double begin_x, double end_x, double width = 1.0) {
  Scenario s;
  s.name = "floor";
  TerrainBox box;
  box.size = Eigen::Vector3d(end_x - begin_x, width, 0.5);
  box.position = Eigen::Vector3d(0.5 * (end_x + begin_x), 0.0, -0.25);
  s.terrain = {box};
  s.terrain_mesh = BuildTerrainMesh(s.terrain);
  return s;
}

/// A floor from x = -1 to `end_x` (1 m wide): the terrain a map knows after seeing that far.
Scenario FloorTo(double end_x) { return FloorFrom(-1.0, end_x); }

/// A root planner on a map that grows (--partial-map), the robot's messages and its answers.
class RootPlannerNodePartialMapTest : public ::testing::Test {
 protected:
  static RootPlannerNodeOptions PartialMap() {
    RootPlannerNodeOptions options;
    options.partial_map = true;
    return options;
  }
  void SetUp() override { node_.status().set_verbose(false); }
  void Pump() {
    while (lcm_.handleTimeout(0) > 0) {
    }
  }
  /// The robot waiting at a step boundary since `utime`, its base at (x, y).
  void WaitAt(int64_t utime, double x, double y = 0.0) {
    rbcp_msgs::controller_status_t controller{};
    rbcp_msgs::robot_state_t state{};
    controller.utime = state.utime = controller.awaiting_since = utime;
    controller.awaiting_plan = true;
    state.base_position[0] = x;
    state.base_position[1] = y;
    state.base_position[2] = 0.45;
    state.base_orientation[0] = 1.0;
    lcm_.publish(channels::kControllerStatus, &controller);
    lcm_.publish(channels::kRobotState, &state);
  }
  /// The operator's request from (0, 0) to (goal_x, 0).
  void Request(int64_t id, double goal_x) {
    rbcp_msgs::plan_request_t request{};
    request.utime = 200;
    request.request_id = id;
    request.use_start = true;
    request.goal_position[0] = goal_x;
    request.time_budget = 5.0;
    request.seed = 3;
    lcm_.publish(channels::kPlanRequest, &request);
  }
  std::string Reason() const { return status_.Latest() ? status_.Latest()->reason : ""; }

  lcm::LCM lcm_{"memq://"};
  RobotModel robot_ = RobotModel::LoadDefault(kConfig);
  RootPlannerNode node_{lcm_, robot_, RootPlannerConfig::LoadFile(kConfig + "/root_planner.yaml", kConfig), PartialMap()};
  transport::LatestMessage<rbcp_msgs::root_path_t> paths_{lcm_, channels::kRootPath};
  transport::LatestMessage<rbcp_msgs::process_status_t> status_{lcm_, channels::kStatus};
};

TEST_F(RootPlannerNodePartialMapTest, PlansTowardsAGoalTheMapDoesNotShowThenToItOnceItDoes) {
  // The map knows the floor to x = 1.5; the goal is at x = 3. The robot waits for its first plan.
  WaitAt(100, 0.0);
  test::PublishWorld(lcm_, FloorTo(1.5), kConfig, 100);
  Request(5, 3.0);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  auto path = paths_.Take();
  ASSERT_TRUE(path.has_value()) << Reason();
  EXPECT_FALSE(path->reaches_goal);
  const double end_x = path->points.back().position[0];
  EXPECT_GT(end_x, 0.5) << "towards the goal";
  EXPECT_LE(end_x, 1.0 + 1e-9) << "on the known terrain, with room for the front feet";
  EXPECT_NE(Reason().find("towards the goal"), std::string::npos) << Reason();

  // The robot waits at a step boundary on the way; the map now shows the goal: a path to it.
  WaitAt(2000000, 0.6);
  test::PublishWorld(lcm_, FloorTo(4.0), kConfig, 2000000);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  path = paths_.Take();
  ASSERT_TRUE(path.has_value()) << Reason();
  EXPECT_TRUE(path->reaches_goal);
  EXPECT_NEAR(path->points.front().position[0], 0.6, 1e-9);
  EXPECT_NEAR(path->points.back().position[0], 3.0, 1e-9);
}

TEST_F(RootPlannerNodePartialMapTest, ARequestIsPlannedOnTheMapOfAWait) {
  test::PublishWorld(lcm_, FloorTo(1.5), kConfig, 100);
  Request(10, 3.0);
  Pump();
  node_.Step();
  Pump();
  EXPECT_FALSE(paths_.Take().has_value()) << "the robot does not wait yet: the map may still grow before it does";
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_NE(Reason().find("the map of that wait"), std::string::npos) << Reason();
  // The robot waits since 1 s; the map it has is older: still no path.
  WaitAt(1000000, 0.0);
  Pump();
  node_.Step();
  Pump();
  EXPECT_FALSE(paths_.Take().has_value());
  // The map of the wait comes: the path, on it.
  test::PublishWorld(lcm_, FloorTo(1.6), kConfig, 1000000);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  const auto path = paths_.Take();
  ASSERT_TRUE(path.has_value()) << Reason();
  EXPECT_EQ(path->terrain_id, transport::TerrainId(FloorTo(1.6).terrain_mesh));
}

TEST_F(RootPlannerNodePartialMapTest, ANewMapIsPlannedOnEvenWhenARepeatedRequestCameWithIt) {
  // A second map of the same wait comes while the path on the first is being planned, and so
  // does the operator's repeat of the request: the repeat is answered, and the path goes on as
  // the path on the newer map, the one the contact planner holds.
  WaitAt(1000000, 0.0);
  test::PublishWorld(lcm_, FloorTo(3.5), kConfig, 1000000);
  Request(9, 2.5);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  const auto first = paths_.Take();
  ASSERT_TRUE(first.has_value()) << Reason();
  test::PublishWorld(lcm_, FloorTo(3.7), kConfig, 1000000);
  Request(9, 2.5);
  Pump();
  ASSERT_TRUE(node_.Step());  // the repeat, answered with the path it has
  Pump();
  const auto repeated = paths_.Take();
  ASSERT_TRUE(repeated.has_value());
  EXPECT_EQ(repeated->terrain_id, first->terrain_id);
  node_.Step();  // the new map
  Pump();
  const auto on_new_map = paths_.Take();
  ASSERT_TRUE(on_new_map.has_value()) << Reason();
  EXPECT_EQ(on_new_map->terrain_id, transport::TerrainId(FloorTo(3.7).terrain_mesh));
}

TEST_F(RootPlannerNodePartialMapTest, APathThatHoldsOnANewMapGoesOnAsThePathOnIt) {
  WaitAt(100, 0.0);
  test::PublishWorld(lcm_, FloorTo(3.5), kConfig, 100);
  Request(8, 2.5);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  const auto first = paths_.Take();
  ASSERT_TRUE(first.has_value()) << Reason();
  ASSERT_TRUE(first->reaches_goal);

  // The robot waits on the path; the map grew a little: the same path, as the path on this map.
  WaitAt(1000000, 0.3);
  test::PublishWorld(lcm_, FloorTo(3.7), kConfig, 1000000);
  Pump();
  node_.Step();
  Pump();
  const auto kept = paths_.Take();
  ASSERT_TRUE(kept.has_value());
  EXPECT_NE(kept->terrain_id, first->terrain_id) << "the path on the new map";
  ASSERT_EQ(kept->num_points, first->num_points) << "the same path";
  for (int i = 0; i < kept->num_points; ++i) EXPECT_EQ(kept->points[i].position[0], first->points[i].position[0]);

  // The next map shows the floor ending before the goal: a new path, towards it.
  WaitAt(2000000, 0.6);
  test::PublishWorld(lcm_, FloorTo(1.8), kConfig, 2000000);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  const auto replanned = paths_.Take();
  ASSERT_TRUE(replanned.has_value()) << Reason();
  EXPECT_FALSE(replanned->reaches_goal);
  EXPECT_NEAR(replanned->points.front().position[0], 0.6, 1e-9);
  EXPECT_LE(replanned->points.back().position[0], 1.8 - 0.5 + 1e-9);
}

TEST_F(RootPlannerNodePartialMapTest, AtTheEndOfAPathShortOfTheGoalTheRobotGetsANewOne) {
  WaitAt(100, 0.0);
  test::PublishWorld(lcm_, FloorTo(1.5), kConfig, 100);
  Request(9, 3.0);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  const auto first = paths_.Take();
  ASSERT_TRUE(first.has_value()) << Reason();
  const double end_x = first->points.back().position[0];

  // The robot waits at the path's end; the map shows a little more (less than the 0.5 m gain that
  // replans a path on the way): a new path from there all the same.
  WaitAt(3000000, end_x);
  test::PublishWorld(lcm_, FloorTo(1.5 + 0.3), kConfig, 3000000);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  const auto next = paths_.Take();
  ASSERT_TRUE(next.has_value()) << Reason();
  EXPECT_NEAR(next->points.front().position[0], end_x, 1e-9) << "from where the robot stands";
  EXPECT_GT(next->points.back().position[0], end_x + 0.2);
}

TEST_F(RootPlannerNodePartialMapTest, WhereTheMapShowsNoWayTheRobotGoesToAnEdgeItHasNotStoodAt) {
  // The map knows the floor from x = -1 to 0.3 only; the robot at x = 0 sees no standing position
  // nearer the goal at x = 3: it goes to an edge of the map at least 0.5 m away (the floor's far
  // end: at its sides the feet would stand off it), facing the goal.
  WaitAt(100, 0.0);
  test::PublishWorld(lcm_, FloorTo(0.3), kConfig, 100);
  Request(6, 3.0);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  auto path = paths_.Take();
  ASSERT_TRUE(path.has_value()) << Reason();
  EXPECT_FALSE(path->reaches_goal);
  EXPECT_NE(Reason().find("an edge of the map"), std::string::npos) << Reason();
  const Eigen::Vector2d end(path->points.back().position[0], path->points.back().position[1]);
  EXPECT_GE(end.norm(), 0.5) << "not where the robot stood";

  // It waits there; the map still shows no way, and no edge it can stand at is 0.5 m from both
  // places it stood at: the replan fails and says so.
  WaitAt(1000000, end.x(), end.y());
  test::PublishWorld(lcm_, FloorTo(0.32), kConfig, 1000000);
  Pump();
  node_.Step();
  Pump();
  ASSERT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(Reason().find("nor an edge of the map the robot has not stood at"), std::string::npos) << Reason();
}

TEST_F(RootPlannerNodePartialMapTest, ARequestTheMapShowsNoWayForIsPlannedAgainOnTheNextMap) {
  // The map knows only the floor under the robot: no standing position nearer the goal, and no
  // edge of the map away from where it stands.
  WaitAt(100, 0.0);
  test::PublishWorld(lcm_, FloorFrom(-0.35, 0.3, 0.6), kConfig, 100);
  Request(6, 3.0);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_FALSE(paths_.Take().has_value());
  ASSERT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(Reason().find("no standing position nearer the goal"), std::string::npos) << Reason();

  // The robot waits where it stands; the next map shows more: a path towards the goal.
  WaitAt(1000000, 0.0);
  test::PublishWorld(lcm_, FloorTo(2.0), kConfig, 1000000);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  const auto path = paths_.Take();
  ASSERT_TRUE(path.has_value()) << Reason();
  EXPECT_FALSE(path->reaches_goal);
}

}  // namespace
}  // namespace rbcp::nodes
