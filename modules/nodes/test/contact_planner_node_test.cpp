#include "rbcp/nodes/contact_planner_node.h"

#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <thread>

#include "rbcp/core/pose.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/nodes/root_planner_node.h"
#include "rbcp/plan_checker/plan_checker.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/transport/convert.h"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "world_messages.h"

namespace rbcp::nodes {
namespace {

const std::string kConfig = std::string(RBCP_SOURCE_DIR) + "/config";

const RobotModel& Robot() {
  static const RobotModel robot = RobotModel::LoadDefault(kConfig);
  return robot;
}

const LimbDatabase& Database() {
  static const LimbDatabase database = LoadLimbDatabase(Robot(), kConfig, false);
  return database;
}

const Scenario& FlatGround() {
  static const Scenario scenario = LoadScenario(kConfig + "/scenarios/flat_ground.yaml");
  return scenario;
}

/// The ROOT_PATH message of the flat_ground scenario's start to goal (planned once).
const rbcp_msgs::root_path_t& FlatGroundRootPath() {
  static const rbcp_msgs::root_path_t msg = [] {
    const Scenario& scenario = FlatGround();
    const auto surfaces =
        AffordanceExtractor(AffordanceConfig::Load(YamlMap::LoadFile(kConfig + "/affordance.yaml"))).Extract(scenario.terrain_mesh);
    const RootPlanner planner(Robot(), RootPlannerConfig::LoadFile(kConfig + "/root_planner.yaml", kConfig));
    const auto start = planner.StandingPosition(scenario.terrain_mesh, scenario.start.position);
    const auto goal = planner.StandingPosition(scenario.terrain_mesh, scenario.goal.position);
    EXPECT_TRUE(start && goal);
    const RootPlanResult r = planner.Plan(scenario.terrain_mesh, surfaces, *start, scenario.start.yaw, *goal,
                                          scenario.goal.yaw, 3, 5.0);
    EXPECT_TRUE(r.ok()) << r.reason;
    return ToRootPathMsg(r, 200, 7, transport::TerrainId(scenario.terrain_mesh));
  }();
  return msg;
}

/// The robot's measured state (ROBOT_STATE) and its controller's status (CONTROLLER_STATUS) at
/// the same time.
struct RobotMsgs {
  rbcp_msgs::robot_state_t state{};
  rbcp_msgs::controller_status_t controller{};
  void SetUtime(int64_t utime) {
    state.utime = utime;
    controller.utime = utime;
  }
  void Publish(lcm::LCM& lcm) const {
    lcm.publish(channels::kControllerStatus, &controller);
    lcm.publish(channels::kRobotState, &state);
  }
};

class ContactPlannerNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm_.good());
    node_ = MakeNode(0);
  }
  /// resend_period_s 0: a plan is never sent again (the tests answer each wait once).
  std::unique_ptr<ContactPlannerNode> MakeNode(int horizon_steps, double resend_period_s = 0.0, bool partial_map = false) {
    ContactPlannerNodeOptions options;
    options.horizon_steps = horizon_steps;
    options.resend_period_s = resend_period_s;
    options.partial_map = partial_map;
    auto node = std::make_unique<ContactPlannerNode>(
        lcm_, Robot(), Database(), EquilibriumConfig::LoadFile(kConfig + "/equilibrium.yaml"),
        ContactPlannerConfig::LoadFile(kConfig + "/contact_planner.yaml"), StanceConfig::LoadFile(kConfig + "/stance.yaml"),
        options);
    node->set_verbose(false);
    return node;
  }
  void Pump() {
    while (lcm_.handleTimeout(0) > 0) {
    }
  }
  void PublishWorld() { test::PublishWorld(lcm_, FlatGround(), kConfig); }
  /// A new node answering waits with at most `horizon_steps` steps, on the flat ground's world
  /// and root path.
  void FollowFlatGroundPath(int horizon_steps) {
    node_ = MakeNode(horizon_steps);
    PublishWorld();
    lcm_.publish(channels::kRootPath, &FlatGroundRootPath());
    Pump();
    ASSERT_TRUE(node_->Step());
  }
  /// Publishes `robot`, steps the node once and returns the CONTACT_PLAN it answered with, if any.
  std::optional<rbcp_msgs::contact_plan_t> Answer(const RobotMsgs& robot) {
    robot.Publish(lcm_);
    Pump();
    node_->Step();
    Pump();
    return plan_.Take();
  }
  /// Publishes a message on `channel`, steps the node once and expects FAILED with no plan; returns
  /// the reason.
  template <typename Msg>
  std::string ExpectFailed(const char* channel, const Msg& msg) {
    lcm_.publish(channel, &msg);
    Pump();
    EXPECT_TRUE(node_->Step());
    Pump();
    EXPECT_FALSE(plan_.Take().has_value());
    if (!status_.Latest()) {
      ADD_FAILURE() << "no STATUS";
      return "";
    }
    EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
    EXPECT_EQ(status_.Latest()->process, "contact_planner");
    return status_.Latest()->reason;
  }
  /// Publishes `robot`, steps the node once and expects FAILED with no plan; returns the reason.
  std::string ExpectFailed(const RobotMsgs& robot) {
    lcm_.publish(channels::kControllerStatus, &robot.controller);
    return ExpectFailed(channels::kRobotState, robot.state);
  }
  /// Publishes a path and expects FAILED with `reason` and no plan.
  void ExpectRejected(const rbcp_msgs::root_path_t& path, const std::string& reason) {
    EXPECT_EQ(ExpectFailed(channels::kRootPath, path), reason);
  }

  lcm::LCM lcm_{"memq://"};
  std::unique_ptr<ContactPlannerNode> node_;
  transport::LatestMessage<rbcp_msgs::contact_plan_t> plan_{lcm_, channels::kContactPlan};
  transport::LatestMessage<rbcp_msgs::process_status_t> status_{lcm_, channels::kStatus};
};

TEST(StanceDeviationTest, SaysWhatDiffersFromThePlannedStanceAndByHowMuch) {
  EXPECT_EQ((StanceDeviation{StanceDeviation::Kind::kFoothold, Leg::kRH, 0.012345}.Describe()),
            "RH stands 0.0123 m from its planned foothold");
  EXPECT_EQ((StanceDeviation{StanceDeviation::Kind::kBaseOrientation, Leg::kLF, 0.0625}.Describe()),
            "the base is 0.0625 rad from its planned orientation");
  EXPECT_EQ((PlanAheadMissed{PlanAheadMissed::Kind::kStanceDeviates,
                             StanceDeviation{StanceDeviation::Kind::kBasePosition, Leg::kLF, 0.05}}
                 .Describe()),
            "the base is 0.05 m off the controller's reference");
  EXPECT_EQ((PlanAheadMissed{PlanAheadMissed::Kind::kNone, std::nullopt}.Describe()), "no plan made ahead");
}

TEST_F(ContactPlannerNodeTest, WaitsForTheWorldThenPlansACheckedPlan) {
  const auto& path = FlatGroundRootPath();
  lcm_.publish(channels::kRootPath, &path);
  Pump();
  EXPECT_FALSE(node_->Step()) << "no terrain yet: the path stays pending";
  PublishWorld();
  Pump();
  ASSERT_TRUE(node_->Step());
  Pump();
  auto msg = plan_.Take();
  ASSERT_TRUE(msg.has_value()) << status_.Latest()->reason;
  EXPECT_EQ(msg->request_id, 7);
  const ContactPlan plan = transport::FromContactPlanMsg(*msg);
  ASSERT_GE(plan.states.size(), 5u);
  EXPECT_EQ(plan.states.front().moving_leg, -1);
  const auto& first = path.points.front().position;
  const auto& last = path.points.back().position;
  EXPECT_LT((plan.states.front().base_position.head<2>() - Eigen::Vector2d(first[0], first[1])).norm(), 1e-6);
  EXPECT_LT((plan.states.back().base_position.head<2>() - Eigen::Vector2d(last[0], last[1])).norm(), 0.2);
  const PlanCheckReport report = CheckPlanForScenario(kConfig, FlatGround(), plan);
  EXPECT_TRUE(report.ok) << report.Summary();

  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
  EXPECT_NE(status_.Latest()->reason.find(std::to_string(plan.states.size() - 1) + " steps"), std::string::npos)
      << status_.Latest()->reason;
  ASSERT_TRUE(node_->last_result().has_value());
  EXPECT_TRUE(node_->last_result()->reached_goal);
  EXPECT_FALSE(node_->Step()) << "a path is planned once";
}

TEST_F(ContactPlannerNodeTest, ARepeatedPathGetsItsPlanAgainAndASecondRunItsOwnPlan) {
  node_ = MakeNode(0, 1e-9);  // a repeat may be answered at once
  PublishWorld();
  const auto& path = FlatGroundRootPath();
  lcm_.publish(channels::kRootPath, &path);
  Pump();
  ASSERT_TRUE(node_->Step());
  Pump();
  const auto first = plan_.Take();
  ASSERT_TRUE(first.has_value()) << status_.Latest()->reason;
  const int64_t handled = status_.Latest()->handled;
  // The root planner repeats its path (for late processes, or answering a repeated request):
  // the plan goes out again, and STATUS keeps its answer (no BUSY left behind).
  lcm_.publish(channels::kRootPath, &path);
  Pump();
  node_->Step();
  Pump();
  const auto again = plan_.Take();
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->plan_seq, first->plan_seq) << "the same plan, not a new search";
  EXPECT_EQ(again->request_id, first->request_id);
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
  EXPECT_EQ(status_.Latest()->handled, handled);
  // The operator runs the same scenario again: a new request, the same path, its own plan.
  auto second_run = path;
  second_run.request_id = 8;
  lcm_.publish(channels::kRootPath, &second_run);
  Pump();
  ASSERT_TRUE(node_->Step());
  Pump();
  const auto second = plan_.Take();
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->request_id, 8);
  EXPECT_EQ(second->plan_seq, first->plan_seq + 1);
  EXPECT_EQ(second->num_states, first->num_states);
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
  EXPECT_EQ(status_.Latest()->handled, handled + 1);
}

TEST_F(ContactPlannerNodeTest, APathPlannedOnAnotherTerrainWaitsForThatTerrain) {
  // The planner holds the plinth; the flat floor's path comes first (its terrain, large, still
  // on its way, or the plinth's path not planned yet): it is not planned on the plinth.
  const Scenario plinth = LoadScenario(kConfig + "/scenarios/plinth.yaml");
  test::PublishWorld(lcm_, plinth, kConfig);
  const auto& path = FlatGroundRootPath();
  lcm_.publish(channels::kRootPath, &path);
  Pump();
  EXPECT_FALSE(node_->Step());
  Pump();
  EXPECT_FALSE(plan_.Take().has_value());
  EXPECT_FALSE(status_.Latest().has_value()) << "a wait, not a failure: " << status_.Latest()->reason;
  // The floor comes: the path is planned on it, and the plan names it.
  PublishWorld();
  Pump();
  ASSERT_TRUE(node_->Step());
  Pump();
  const auto plan = plan_.Take();
  ASSERT_TRUE(plan.has_value()) << status_.Latest()->reason;
  EXPECT_EQ(plan->terrain_id, path.terrain_id);
  EXPECT_EQ(plan->terrain_id, transport::TerrainId(FlatGround().terrain_mesh));
}

TEST_F(ContactPlannerNodeTest, InvalidPathsFailWithAReasonAndNoPlan) {
  PublishWorld();
  Pump();
  EXPECT_FALSE(node_->Step()) << "nothing to plan yet";

  auto path = FlatGroundRootPath();
  path.points[3].position[1] = std::numeric_limits<double>::quiet_NaN();
  ExpectRejected(path, "root path: point 3 is not finite");

  path = FlatGroundRootPath();
  path.points.clear();
  path.num_points = 0;
  ExpectRejected(path, "root path: no point");

  path = FlatGroundRootPath();
  path.points[5].orientation[0] = 0.0;
  ExpectRejected(path, "root path: point 5: orientation is not a unit quaternion");

  path = FlatGroundRootPath();
  path.points[2].t = path.points[1].t;
  ExpectRejected(path, "root path: point 2: times must increase, got t = " + std::to_string(path.points[2].t) +
                           " s after " + std::to_string(path.points[1].t) + " s");

  path = FlatGroundRootPath();
  path.points.back().position[0] = 40.0;  // far beyond the floor
  ExpectRejected(path, "root path: point " + std::to_string(path.num_points - 1) +
                           " at (40, 0) is off the terrain (x in [-1.75, 6.75], y in [-1.5, 1.5])");

  path = FlatGroundRootPath();
  for (auto& p : path.points) p.t *= 1e8;  // spanning about 1e9 s
  const std::string duration = std::to_string(path.points.back().t - path.points.front().t);
  ExpectRejected(path, "root path: lasts " + duration + " s, more than the limit of 3600 s");

  path = FlatGroundRootPath();
  path.points.front().position[0] = -2.0;  // 0.25 m beyond the floor's edge
  ExpectRejected(path, "root path: the start (-2, 0) is not above the terrain");
  EXPECT_FALSE(node_->last_result().has_value());

  // The node still plans a valid path afterwards.
  lcm_.publish(channels::kRootPath, &FlatGroundRootPath());
  Pump();
  ASSERT_TRUE(node_->Step());
  Pump();
  EXPECT_TRUE(plan_.Take().has_value()) << status_.Latest()->reason;
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
}

/// The robot standing in the reference configuration at (x, y), waiting for a plan since utime.
RobotMsgs WaitingState(int64_t utime, double x, double y) {
  RobotMsgs robot;
  rbcp_msgs::robot_state_t& state = robot.state;
  state.base_position[0] = x;
  state.base_position[1] = y;
  state.base_position[2] = Robot().NominalBaseHeight();
  state.base_orientation[0] = 1.0;
  for (int j = 0; j < kNumJoints; ++j) state.joint_position[j] = Robot().ReferenceConfiguration()[j];
  for (auto& c : state.foot_contact) c = 1;
  robot.SetUtime(utime);
  robot.controller.awaiting_plan = true;
  robot.controller.awaiting_since = utime;
  robot.controller.phase = "await";
  return robot;
}

TEST_F(ContactPlannerNodeTest, HorizonModeAnswersEachWaitWithKStepsFromTheMeasuredStance) {
  constexpr int kSteps = 3;
  node_ = MakeNode(kSteps);
  PublishWorld();
  lcm_.publish(channels::kRootPath, &FlatGroundRootPath());
  Pump();
  ASSERT_TRUE(node_->Step());  // takes the path
  Pump();
  EXPECT_FALSE(plan_.Take().has_value()) << "no plan before the robot waits for one";

  RobotMsgs state = WaitingState(300, 0.02, 0.01);
  state.Publish(lcm_);
  Pump();
  ASSERT_TRUE(node_->Step());
  Pump();
  auto msg = plan_.Take();
  ASSERT_TRUE(msg.has_value()) << status_.Latest()->reason;
  EXPECT_EQ(msg->plan_seq, 1);
  EXPECT_EQ(msg->start_utime, 300);
  EXPECT_FALSE(msg->reaches_goal);
  EXPECT_EQ(status_.Latest()->input_utime, 300);
  const ContactPlan plan = transport::FromContactPlanMsg(*msg);
  ASSERT_EQ(plan.states.size(), static_cast<std::size_t>(kSteps + 1));
  EXPECT_EQ(plan.states.front().moving_leg, -1);
  EXPECT_LT((plan.states.front().base_position.head<2>() - Eigen::Vector2d(0.02, 0.01)).norm(), 1e-9)
      << "the horizon starts at the measured base";
  const Eigen::Isometry3d base_W(Eigen::Translation3d(0.02, 0.01, Robot().NominalBaseHeight()));
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d fk =
        base_W * Robot().FootPosition(leg, Robot().ReferenceConfiguration().segment<3>(3 * Index(leg)));
    const Eigen::Vector3d& foot = plan.states.front().feet[static_cast<std::size_t>(Index(leg))].position;
    EXPECT_LT((foot.head<2>() - fk.head<2>()).norm(), 1e-9) << "the measured feet, " << LegName(leg);
    EXPECT_NEAR(foot.z(), 0.0, 1e-9) << "on the floor";
  }
  const PlanCheckReport report = CheckPlanForScenario(kConfig, FlatGround(), plan);
  EXPECT_TRUE(report.ok) << report.Summary();

  // The same wait is answered once.
  state.SetUtime(310);
  state.Publish(lcm_);
  Pump();
  EXPECT_FALSE(node_->Step());
  Pump();
  EXPECT_FALSE(plan_.Take().has_value());

  // A new wait with the base far from the path is rejected with the reason.
  std::string reason = ExpectFailed(WaitingState(400, 0.02, 1.0));
  EXPECT_NE(reason.find("from the root path"), std::string::npos) << reason;
  EXPECT_EQ(status_.Latest()->input_utime, 400);

  // So is one with a foot in the air.
  state = WaitingState(500, 0.02, 0.01);
  state.state.joint_position[1] += 0.6;  // LF_HFE: the foot swings forward and up
  reason = ExpectFailed(state);
  EXPECT_NE(reason.find("measured stance: LF foot"), std::string::npos) << reason;
}

TEST_F(ContactPlannerNodeTest, OnAGrowingMapAPathToTheGoalAcrossUnseenCellsGetsTheStepsTheMapShows) {
  // The map shows the floor to x = 1 and again from x = 1.8 (the cells between are not seen
  // yet); the path goes on to the goal at x = 5. No plan reaches it, but the steps the map shows
  // are walked: the robot then sees more.
  constexpr int kSteps = 3;
  node_ = MakeNode(kSteps, 0.0, /*partial_map=*/true);
  Scenario seen;
  seen.name = "seen";
  for (const auto& [from, to] : {std::pair{-1.0, 1.0}, std::pair{1.8, 6.0}}) {
    TerrainBox box;
    box.size = Eigen::Vector3d(to - from, 1.0, 0.5);
    box.position = Eigen::Vector3d(0.5 * (from + to), 0.0, -0.25);
    seen.terrain.push_back(box);
  }
  seen.terrain_mesh = BuildTerrainMesh(seen.terrain);
  test::PublishWorld(lcm_, seen, kConfig, 300);
  rbcp_msgs::root_path_t path = FlatGroundRootPath();
  path.terrain_id = transport::TerrainId(seen.terrain_mesh);
  path.reaches_goal = true;
  lcm_.publish(channels::kRootPath, &path);
  Pump();
  ASSERT_TRUE(node_->Step());  // takes the path
  const auto msg = Answer(WaitingState(300, 0.02, 0.01));
  ASSERT_TRUE(msg.has_value()) << status_.Latest()->reason;
  EXPECT_FALSE(msg->reaches_goal);
  const ContactPlan plan = transport::FromContactPlanMsg(*msg);
  ASSERT_EQ(plan.states.size(), static_cast<std::size_t>(kSteps + 1));
  for (const WholeBodyState& state : plan.states) {
    for (const auto& foot : state.feet) EXPECT_LT(foot.position.x(), 1.0) << "on the floor the map shows";
  }
}

TEST_F(ContactPlannerNodeTest, OnAGrowingMapFeetOnThePlansFootholdsStandThereWhenTheNewMapLostTheirSurface) {
  // The map of the next wait shows no contact surface under the hind feet any more (the floor
  // there left the map's window): they still stand on the footholds the last plan gave them, and
  // the wait is answered.
  constexpr int kSteps = 2;
  node_ = MakeNode(kSteps, 0.0, /*partial_map=*/true);
  const auto floor = [](double from, double to) {
    Scenario s;
    s.name = "floor";
    TerrainBox box;
    box.size = Eigen::Vector3d(to - from, 1.0, 0.5);
    box.position = Eigen::Vector3d(0.5 * (from + to), 0.0, -0.25);
    s.terrain = {box};
    s.terrain_mesh = BuildTerrainMesh(s.terrain);
    return s;
  };
  const Scenario before = floor(-1.0, 6.0), after = floor(-0.15, 6.0);
  test::PublishWorld(lcm_, before, kConfig, 300);
  rbcp_msgs::root_path_t path = FlatGroundRootPath();
  path.terrain_id = transport::TerrainId(before.terrain_mesh);
  lcm_.publish(channels::kRootPath, &path);
  Pump();
  ASSERT_TRUE(node_->Step());
  ASSERT_TRUE(Answer(WaitingState(300, 0.02, 0.01)).has_value()) << status_.Latest()->reason;

  test::PublishWorld(lcm_, after, kConfig, 400);
  path.terrain_id = transport::TerrainId(after.terrain_mesh);
  lcm_.publish(channels::kRootPath, &path);
  Pump();
  node_->Step();
  const auto msg = Answer(WaitingState(400, 0.02, 0.01));
  ASSERT_TRUE(msg.has_value()) << status_.Latest()->reason;
  const ContactPlan plan = transport::FromContactPlanMsg(*msg);
  for (Leg leg : {Leg::kLH, Leg::kRH}) {
    EXPECT_LT(plan.states.front().feet[static_cast<std::size_t>(Index(leg))].position.x(), -0.15) << LegName(leg);
  }
}

TEST_F(ContactPlannerNodeTest, APlanIsSentAgainWhileTheRobotStillWaitsForIt) {
  // A lossy link lost the plan: the robot goes on waiting at the same stance, and gets the same
  // plan again instead of waiting out its timeout.
  node_ = MakeNode(3, 1e-6);
  PublishWorld();
  lcm_.publish(channels::kRootPath, &FlatGroundRootPath());
  Pump();
  ASSERT_TRUE(node_->Step());
  RobotMsgs state = WaitingState(300, 0.02, 0.01);
  const auto first = Answer(state);
  ASSERT_TRUE(first.has_value()) << status_.Latest()->reason;
  state.SetUtime(310);  // the same wait, a later state
  state.Publish(lcm_);
  Pump();
  std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(node_->Step());
  Pump();
  const auto again = plan_.Take();
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->plan_seq, first->plan_seq);
  EXPECT_EQ(again->start_utime, 300);
  EXPECT_EQ(again->num_states, first->num_states);
  // Walking (no wait), nothing is sent.
  state.SetUtime(320);
  state.controller.awaiting_plan = false;
  state.Publish(lcm_);
  Pump();
  std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_FALSE(node_->Step());
  Pump();
  EXPECT_FALSE(plan_.Take().has_value());
}

TEST_F(ContactPlannerNodeTest, AnOlderPathOfTheSameGoalComingLateIsIgnored) {
  ASSERT_NO_FATAL_FAILURE(FollowFlatGroundPath(3));
  // The same goal's path from before (the network reordered it), one metre to the side: were it
  // followed, the robot would stand too far from it to plan.
  rbcp_msgs::root_path_t older = FlatGroundRootPath();
  older.utime -= 100;
  for (auto& p : older.points) p.position[1] += 1.0;
  lcm_.publish(channels::kRootPath, &older);
  Pump();
  node_->Step();
  const auto plan = Answer(WaitingState(300, 0.02, 0.01));
  ASSERT_TRUE(plan.has_value()) << status_.Latest()->reason;
  EXPECT_EQ(plan->start_utime, 300);
}

/// The state of a robot waiting after it walked `walked` steps of `plan` (plan_seq `seq`), on
/// that plan's footholds with its base `offset_W` off the planned pose.
/// A robot waiting after `walked` steps of `plan` (plan_seq `seq`), its base `offset_W` off the
/// plan's pose and `base_error_m` off the reference its controller tracks.
RobotMsgs WaitingOnPlan(int64_t utime, const ContactPlan& plan, int walked, int64_t seq, const Eigen::Vector3d& offset_W,
                        double base_error_m) {
  const WholeBodyState& s = plan.states[static_cast<std::size_t>(walked)];
  RobotMsgs robot = WaitingState(utime, 0.0, 0.0);
  rbcp_msgs::robot_state_t& state = robot.state;
  const Eigen::Vector3d p = s.base_position + offset_W;
  const Eigen::Quaterniond orientation(RotationFromRpy(s.base_rpy));
  const Eigen::Isometry3d base_W = Eigen::Translation3d(p) * orientation;
  for (int i = 0; i < 3; ++i) state.base_position[i] = p[i];
  state.base_orientation[0] = orientation.w();
  state.base_orientation[1] = orientation.x();
  state.base_orientation[2] = orientation.y();
  state.base_orientation[3] = orientation.z();
  for (Leg leg : kAllLegs) {
    const IkResult ik = Robot().SolveLegIk(leg, base_W.inverse() * s.feet[static_cast<std::size_t>(Index(leg))].position);
    EXPECT_TRUE(ik.ok()) << LegName(leg);
    for (int j = 0; j < 3; ++j) state.joint_position[3 * Index(leg) + j] = ik.q[j];
  }
  robot.controller.plan_seq = seq;
  robot.controller.steps_done = walked;
  robot.controller.base_error = base_error_m;
  return robot;
}

TEST_F(ContactPlannerNodeTest, OnThePlannedFootholdsTheBaseStandsWhereThePlanPutIt) {
  // With every foot on the plan's footholds and the base on the reference its controller tracks,
  // the next plan starts from the planned base pose: the base is off that pose by the controller's
  // tracking error, or by a dynamic walk's sway (which its reference has too). Off the reference
  // (a push), it starts from the measured pose.
  struct Case {
    double offset;      ///< the measured base off the plan's pose [m]
    double base_error;  ///< the measured base off the controller's reference [m]
    bool planned_pose;  ///< the next plan starts from the plan's pose
  };
  for (const Case c : {Case{0.02, 0.02, true}, Case{0.12, 0.01, true}, Case{0.10, 0.10, false}}) {
    const double offset = c.offset;
    SCOPED_TRACE("base offset " + std::to_string(offset) + ", off the reference " + std::to_string(c.base_error));
    ASSERT_NO_FATAL_FAILURE(FollowFlatGroundPath(3));
    const auto first = Answer(WaitingState(300, 0.02, 0.01));
    ASSERT_TRUE(first.has_value()) << status_.Latest()->reason;
    const ContactPlan plan = transport::FromContactPlanMsg(*first);
    ASSERT_GE(plan.states.size(), 2u);

    const Eigen::Vector3d offset_W(0.0, offset, 0.0);
    WaitingOnPlan(900, plan, 1, first->plan_seq, offset_W, c.base_error).Publish(lcm_);
    Pump();
    ASSERT_TRUE(node_->Step());
    Pump();
    const auto next = plan_.Take();
    ASSERT_TRUE(next.has_value()) << status_.Latest()->reason;
    EXPECT_EQ(next->start_utime, 900);
    const WholeBodyState start = transport::FromContactPlanMsg(*next).states.front();
    const Eigen::Vector3d expected = plan.states[1].base_position + (c.planned_pose ? Eigen::Vector3d::Zero() : offset_W);
    EXPECT_LT((start.base_position - expected).norm(), 1e-9) << start.base_position.transpose();
    for (std::size_t i = 0; i < start.feet.size(); ++i) {
      EXPECT_LT((start.feet[i].position - plan.states[1].feet[i].position).norm(), 1e-9) << "the planned footholds";
    }
  }
}

TEST_F(ContactPlannerNodeTest, APlanMadeAheadHoldsFromAStanceWithOneFootBesideItsFoothold) {
  // One foot touched down 2.5 cm beside its foothold, the base 5 cm off the plan's pose but on
  // the controller's reference: the plan made ahead goes on from there (its base pose, that foot
  // where it stands). With the base off the reference too (a push), the next plan starts from the
  // measured base.
  for (const double base_error : {0.01, 0.10}) {
    SCOPED_TRACE("off the reference " + std::to_string(base_error));
    ASSERT_NO_FATAL_FAILURE(FollowFlatGroundPath(3));
    const auto first = Answer(WaitingState(300, 0.02, 0.01));
    ASSERT_TRUE(first.has_value()) << status_.Latest()->reason;
    const ContactPlan plan = transport::FromContactPlanMsg(*first);
    ASSERT_GE(plan.states.size(), 3u);

    ContactPlan walked = plan;  // the robot's stance after the first step, one foot off
    const std::size_t off = static_cast<std::size_t>(plan.states[2].moving_leg == 0 ? 1 : 0);
    walked.states[1].feet[off].position += Eigen::Vector3d(0.02, 0.015, 0.0);
    const Eigen::Vector3d offset_W(0.0, 0.05, 0.0);
    const auto next = Answer(WaitingOnPlan(900, walked, 1, first->plan_seq, offset_W, base_error));
    ASSERT_TRUE(next.has_value()) << status_.Latest()->reason;
    const WholeBodyState start = transport::FromContactPlanMsg(*next).states.front();
    const Eigen::Vector3d base = plan.states[1].base_position + (base_error < 0.08 ? Eigen::Vector3d::Zero() : offset_W);
    EXPECT_LT((start.base_position - base).norm(), 1e-9) << start.base_position.transpose();
    EXPECT_LT((start.feet[off].position - walked.states[1].feet[off].position).norm(), 1e-6);
  }
}

TEST_F(ContactPlannerNodeTest, ThePieceMadeAheadKeepsTheStepsTheControllerCommittedTo) {
  // A dynamic walk's CoM already moves toward the support of the steps in its preview: the next
  // piece of plan keeps them as they were, and the new search begins after them.
  ASSERT_NO_FATAL_FAILURE(FollowFlatGroundPath(4));
  RobotMsgs waiting = WaitingState(300, 0.02, 0.01);
  waiting.controller.steps_committed = 2;
  const auto first = Answer(waiting);
  ASSERT_TRUE(first.has_value()) << status_.Latest()->reason;
  const ContactPlan plan = transport::FromContactPlanMsg(*first);
  ASSERT_EQ(plan.states.size(), 5u);

  const auto next = Answer(WaitingOnPlan(900, plan, 1, first->plan_seq, Eigen::Vector3d::Zero(), 0.0));
  ASSERT_TRUE(next.has_value()) << status_.Latest()->reason;
  const ContactPlan piece = transport::FromContactPlanMsg(*next);
  ASSERT_EQ(piece.states.size(), 5u);
  for (std::size_t i = 1; i <= 2; ++i) {
    SCOPED_TRACE("kept step " + std::to_string(i));
    EXPECT_EQ(piece.states[i].moving_leg, plan.states[i + 1].moving_leg);
    EXPECT_LT((piece.states[i].base_position - plan.states[i + 1].base_position).norm(), 1e-9);
    for (std::size_t f = 0; f < piece.states[i].feet.size(); ++f) {
      EXPECT_LT((piece.states[i].feet[f].position - plan.states[i + 1].feet[f].position).norm(), 1e-9);
    }
  }
  const PlanCheckReport report = CheckPlanForScenario(kConfig, FlatGround(), piece);
  EXPECT_TRUE(report.ok) << report.Summary();
}

/// A plan whose base advances along x by `dx` per step, `steps` steps.
ContactPlan StraightPlan(int steps, double dx, bool reaches_goal = false) {
  ContactPlan plan;
  for (int i = 0; i <= steps; ++i) {
    WholeBodyState s;
    s.base_position = Eigen::Vector3d(dx * i, 0.0, 0.45);
    plan.states.push_back(s);
  }
  plan.reaches_goal = reaches_goal;
  return plan;
}

TEST(KeepEarlierSearch, TheEarlierSearchGoesOnWhenTheNewPlanGetsLessFarOrFails) {
  // Progress: centimetres along x.
  const auto progress = [](const WholeBodyState& s) { return static_cast<std::size_t>(std::lround(100.0 * s.base_position.x())); };
  constexpr int kK = 3, kMargin = 4;
  ContactPlanResult fresh;
  fresh.ok = true;
  fresh.plan = StraightPlan(11, 0.05);
  // A long continuation that gets further in K steps goes on; one that gets as far or less does not.
  EXPECT_TRUE(KeepEarlierSearch(StraightPlan(10, 0.08), fresh, kK, kMargin, progress));
  EXPECT_FALSE(KeepEarlierSearch(StraightPlan(10, 0.05), fresh, kK, kMargin, progress));
  EXPECT_FALSE(KeepEarlierSearch(StraightPlan(10, 0.02), fresh, kK, kMargin, progress));
  // Too short to hold K steps and the margin: the new plan, unless the continuation reaches the goal.
  EXPECT_FALSE(KeepEarlierSearch(StraightPlan(6, 0.08), fresh, kK, kMargin, progress));
  EXPECT_TRUE(KeepEarlierSearch(StraightPlan(6, 0.08, true), fresh, kK, kMargin, progress));
  EXPECT_TRUE(KeepEarlierSearch(StraightPlan(2, 0.08, true), fresh, kK, kMargin, progress)) << "the state after K: its end";
  // A failed new search: any step left of the earlier one goes on.
  fresh.ok = false;
  EXPECT_TRUE(KeepEarlierSearch(StraightPlan(1, 0.0), fresh, kK, kMargin, progress));
  EXPECT_FALSE(KeepEarlierSearch(StraightPlan(0, 0.0), fresh, kK, kMargin, progress));
}

TEST_F(ContactPlannerNodeTest, MalformedWorldFailsWithAReason) {
  auto terrain = transport::ToTerrainMsg(FlatGround().terrain_mesh, 100, "flat_ground");
  terrain.vertices[0][2] = std::numeric_limits<double>::quiet_NaN();
  lcm_.publish(channels::kTerrain, &terrain);
  Pump();
  ASSERT_TRUE(node_->Step());
  Pump();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_FALSE(status_.Latest()->reason.empty());
  lcm_.publish(channels::kRootPath, &FlatGroundRootPath());
  Pump();
  EXPECT_FALSE(node_->Step()) << "no valid terrain: the path waits";
  EXPECT_FALSE(plan_.Take().has_value());
}

}  // namespace
}  // namespace rbcp::nodes
