// The simulator's node over memq://: what it publishes, a plan walked to its verdict on STATUS,
// a malformed plan answered with FAILED while the world goes on, and the replanning handshake
// (a wait at every step boundary, stale plans dropped, the planner's failure answered).
#include "rbcp/core/format.h"
#include "rbcp/sim/sim_node.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <thread>

#include "flat_ground_plan.h"
#include "rbcp/controller/controller_config.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"
#include "rbcp/core/error.h"
#include "rbcp/sim/world_events.h"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/point_cloud_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::sim {
namespace {

using rbcp::test::ConfigDir;
using rbcp::test::ScenarioPath;

/// Every message of one type heard on a channel.
template <class Msg>
class Recorder {
 public:
  Recorder(lcm::LCM& lcm, const std::string& channel) : lcm_(lcm) { sub_ = lcm.subscribe(channel, &Recorder::On, this); }
  ~Recorder() { lcm_.unsubscribe(sub_); }
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;
  std::vector<Msg> messages;

 private:
  void On(const lcm::ReceiveBuffer*, const std::string&, const Msg* msg) { messages.push_back(*msg); }
  lcm::LCM& lcm_;
  lcm::Subscription* sub_ = nullptr;
};

/// The simulated world and the test's LCM subscriptions, without a node.
class SimWorld : public ::testing::Test {
 protected:
  void Pump() {
    while (lcm_.handleTimeout(0) > 0) {
    }
  }

  RobotModel robot_ = RobotModel::LoadDefault(ConfigDir());
  SimConfig config_ = SimConfig::LoadFile(ConfigDir() + "/sim.yaml");
  Scenario scenario_ = LoadScenario(ScenarioPath("flat_ground"));
  PlanExecution execution_{robot_, scenario_, config_, ControllerConfig::LoadFile(ConfigDir() + "/controller.yaml"),
                           StanceRules::LoadFromDir(ConfigDir())};
  lcm::LCM lcm_{"memq://"};
  transport::LatestMessage<rbcp_msgs::robot_state_t> states_{lcm_, channels::kRobotState};
  transport::LatestMessage<rbcp_msgs::controller_status_t> controllers_{lcm_, channels::kControllerStatus};
  transport::LatestMessage<rbcp_msgs::terrain_mesh_t> terrain_{lcm_, channels::kTerrain};
  transport::LatestMessage<rbcp_msgs::process_status_t> status_{lcm_, channels::kStatus};
  Recorder<rbcp_msgs::point_cloud_t> clouds_{lcm_, channels::kPointCloud};
  Recorder<rbcp_msgs::robot_state_t> all_states_{lcm_, channels::kRobotState};
  /// The terrain the simulated world stands on, as a planner's plans name it.
  int64_t WorldTerrainId() const { return transport::TerrainId(execution_.CurrentWorld().terrain_mesh); }
};

class SimNodeTest : public SimWorld {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm_.good());
    node_.status().set_verbose(false);
  }
  /// Ticks until `done` or `seconds` of simulated time passed.
  template <typename Done>
  void TickFor(double seconds, Done done) {
    const long ticks = std::lround(seconds * config_.control_rate_hz);
    for (long k = 0; k < ticks && !done(); ++k) {
      node_.Tick();
      Pump();
    }
  }

  SimNode node_{lcm_, execution_, scenario_, config_};
};

TEST_F(SimNodeTest, PublishesTheTerrainAndTheStateAtTheControlRate) {
  TickFor(1.5, [] { return false; });
  ASSERT_TRUE(terrain_.Latest().has_value());
  EXPECT_EQ(terrain_.received(), 2);  // at start and after one simulated second
  EXPECT_EQ(terrain_.Latest()->scenario_name, "flat_ground");
  EXPECT_EQ(static_cast<std::size_t>(terrain_.Latest()->num_triangles), scenario_.terrain_mesh.NumTriangles());
  EXPECT_EQ(states_.received(), 600);  // 400 Hz of simulated time
  const RobotState state = transport::FromRobotStateMsg(*states_.Latest());
  EXPECT_NEAR(state.t, 1.5, 1e-9);
  for (bool c : state.foot_contact) EXPECT_TRUE(c);
  double weight = 0.0;
  for (const Eigen::Vector3d& f : state.foot_force_W) weight += f.z();
  EXPECT_NEAR(weight, robot_.TotalMass() * 9.81, 0.05 * robot_.TotalMass() * 9.81);
  node_.Heartbeat();
  Pump();
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->process, "anymal_sim");
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::ALIVE);
}

/// The simulator with the planners on a perceived terrain (the map of its sensors' clouds).
SimNodeOptions Perceived(bool replan = false) {
  SimNodeOptions o;
  o.terrain = TerrainSource::kPerceived;
  o.replan = replan;
  return o;
}

/// The terrain mapper's STATUS: a perceived world starts once it is heard.
void PublishMapperUp(lcm::LCM& lcm) {
  rbcp_msgs::process_status_t up{};
  up.process = "terrain_mapper";
  up.state = rbcp_msgs::process_status_t::ALIVE;
  lcm.publish(channels::kStatus, &up);
}

TEST_F(SimWorld, OnAPerceivedTerrainPointCloudsGoOutAtTheSensingRateWithTheStatesUtimes) {
  SimNode node(lcm_, execution_, scenario_, config_, Perceived());
  node.status().set_verbose(false);
  transport::LatestMessage<rbcp_msgs::terrain_mesh_t> truth(lcm_, channels::kTerrainTruth);
  // Before the mapper listens nothing goes out and the world stands still.
  for (int k = 0; k < 20; ++k) {
    node.Tick();
    Pump();
  }
  EXPECT_EQ(node.SimTime(), 0.0);
  EXPECT_TRUE(clouds_.messages.empty());
  EXPECT_TRUE(all_states_.messages.empty());
  PublishMapperUp(lcm_);
  Pump();
  for (int k = 0; k < 220; ++k) {  // 0.55 s
    node.Tick();
    Pump();
  }
  EXPECT_FALSE(terrain_.Latest().has_value()) << "the planners' TERRAIN is the mapper's";
  ASSERT_TRUE(truth.Latest().has_value()) << "the true terrain, for judging the map";
  EXPECT_EQ(truth.Latest()->scenario_name, "flat_ground");
  ASSERT_EQ(config_.sensing.rate_hz, 10.0);
  ASSERT_TRUE(config_.sensing.front_camera.enabled && config_.sensing.rear_camera.enabled);
  ASSERT_EQ(clouds_.messages.size(), 10u) << "5 captures in 0.55 s, front and rear";
  EXPECT_EQ(node.PointClouds(), 10);
  std::map<int64_t, rbcp_msgs::robot_state_t> states;
  for (const auto& s : all_states_.messages) states[s.utime] = s;
  for (std::size_t i = 0; i < clouds_.messages.size(); ++i) {
    const rbcp_msgs::point_cloud_t& c = clouds_.messages[i];
    SCOPED_TRACE(c.sensor + " " + std::to_string(c.seq));
    EXPECT_EQ(c.sensor, i % 2 == 0 ? "front_camera" : "rear_camera");
    EXPECT_EQ(c.seq, static_cast<int64_t>(i / 2 + 1));
    EXPECT_EQ(c.utime, 100000 * c.seq) << "every 0.1 s of simulated time";
    ASSERT_EQ(states.count(c.utime), 1u) << "a ROBOT_STATE of the same utime";
    for (int k = 0; k < 3; ++k) EXPECT_EQ(c.base_position[k], states[c.utime].base_position[k]) << "its base pose";
    for (int k = 0; k < 4; ++k) EXPECT_EQ(c.base_orientation[k], states[c.utime].base_orientation[k]);
    EXPECT_EQ(c.num_rays, config_.sensing.front_camera.columns * config_.sensing.front_camera.rows);
    EXPECT_EQ(c.num_points, static_cast<int32_t>(c.points.size()));
    ASSERT_GT(c.num_points, c.num_rays / 2);
    // Placed with that state's base pose and the mount, the points lie on the flat ground (z = 0).
    const RobotState state = transport::FromRobotStateMsg(states[c.utime]);
    Eigen::Isometry3d sensor_W = Eigen::Isometry3d::Identity();
    sensor_W.linear() = state.base_orientation_W.toRotationMatrix() *
                        Eigen::Quaterniond(c.mount_orientation[0], c.mount_orientation[1], c.mount_orientation[2],
                                           c.mount_orientation[3]).toRotationMatrix();
    sensor_W.translation() = state.base_position_W + state.base_orientation_W.toRotationMatrix() *
                                                         Eigen::Vector3d(c.mount_position[0], c.mount_position[1],
                                                                         c.mount_position[2]);
    double worst = 0.0;
    for (const auto& p : c.points) {
      worst = std::max(worst, std::abs((sensor_W * Eigen::Vector3d(p[0], p[1], p[2])).z()));
    }
    EXPECT_LT(worst, 5.0 * c.range_noise_std);
  }
}

TEST_F(SimWorld, OnTheGroundTruthNoSensorRuns) {
  ASSERT_TRUE(config_.sensing.enabled);
  SimNode node(lcm_, execution_, scenario_, config_);
  node.status().set_verbose(false);
  for (int k = 0; k < 200; ++k) {
    node.Tick();
    Pump();
  }
  EXPECT_EQ(all_states_.messages.size(), 200u);
  EXPECT_TRUE(clouds_.messages.empty());
  EXPECT_TRUE(terrain_.Latest().has_value());
}

TEST_F(SimWorld, APerceivedTerrainNeedsASensor) {
  SimConfig config = config_;
  config.sensing.enabled = false;
  EXPECT_THROW(SimNode(lcm_, execution_, scenario_, config, Perceived()), InputError);
}

TEST_F(SimNodeTest, WalksAPlanAndReportsTheVerdict) {
  TickFor(0.3, [] { return false; });
  const auto plan = transport::ToContactPlanMsg(rbcp::test::BuildFlatGroundPlan(robot_, 2, 0.08), 0, 7, WorldTerrainId());
  lcm_.publish(channels::kContactPlan, &plan);
  Pump();
  TickFor(1.0, [] { return false; });
  // The contact planner sends the plan again (for a process that missed it): the walk goes on.
  lcm_.publish(channels::kContactPlan, &plan);
  Pump();
  TickFor(20.0, [&] { return node_.Decided(); });
  ASSERT_TRUE(node_.Decided());
  EXPECT_EQ(node_.Plans(), 1) << "the repeat is not a new plan";
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK) << status_.Latest()->reason;
  EXPECT_NE(status_.Latest()->reason.find("goal reached"), std::string::npos);
}

TEST_F(SimNodeTest, APlanMadeOnAnotherTerrainIsNotWalked) {
  TickFor(0.3, [] { return false; });
  ASSERT_TRUE(terrain_.Latest().has_value());
  EXPECT_EQ(terrain_.Latest()->terrain_id, WorldTerrainId());
  const ContactPlan plan = rbcp::test::BuildFlatGroundPlan(robot_, 2, 0.08);
  const auto elsewhere = transport::ToContactPlanMsg(plan, 0, 7, WorldTerrainId() + 1);
  lcm_.publish(channels::kContactPlan, &elsewhere);
  Pump();
  TickFor(0.5, [] { return false; });
  EXPECT_EQ(node_.Plans(), 0);
  EXPECT_EQ(node_.StalePlans(), 1);
  const auto here = transport::ToContactPlanMsg(plan, 0, 7, WorldTerrainId());
  lcm_.publish(channels::kContactPlan, &here);
  Pump();
  TickFor(0.1, [] { return false; });
  EXPECT_EQ(node_.Plans(), 1);
}

TEST_F(SimNodeTest, AMalformedPlanIsRejectedAndTheRobotKeepsStanding) {
  auto plan = transport::ToContactPlanMsg(rbcp::test::BuildFlatGroundPlan(robot_, 2, 0.08), 0, 7, WorldTerrainId());
  plan.states[1].base_position[2] = std::numeric_limits<double>::quiet_NaN();
  lcm_.publish(channels::kContactPlan, &plan);
  Pump();
  TickFor(0.5, [] { return false; });
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(status_.Latest()->reason.find("rejected CONTACT_PLAN"), std::string::npos) << status_.Latest()->reason;
  EXPECT_FALSE(node_.Decided());
  const RobotState state = transport::FromRobotStateMsg(*states_.Latest());
  for (bool c : state.foot_contact) EXPECT_TRUE(c);
}

TEST_F(SimNodeTest, APlanOfThousandsOfStepsIsRejectedAndTheRobotKeepsStanding) {
  ContactPlan plan = rbcp::test::BuildFlatGroundPlan(robot_, 2, 0.08);
  while (plan.states.size() < PlanExecution::kMaxPlanSteps + 2) plan.states.push_back(plan.states.back());
  const auto msg = transport::ToContactPlanMsg(plan, 0, 7, WorldTerrainId());
  lcm_.publish(channels::kContactPlan, &msg);
  Pump();
  TickFor(0.2, [] { return false; });
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(status_.Latest()->reason.find("expected a plan of at most 2000 steps, got 2001"), std::string::npos)
      << status_.Latest()->reason;
  EXPECT_FALSE(node_.Decided());
  EXPECT_EQ(node_.Plans(), 0);
}

class ReplanningSimNodeTest : public SimWorld {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm_.good());
    replanning_.status().set_verbose(false);
  }
  static SimNodeOptions Options() {
    SimNodeOptions o;
    o.replan = true;
    o.retry_hold_s = 0.5;
    o.max_failed_waits = 2;
    return o;
  }
  SimNode replanning_{lcm_, execution_, scenario_, config_, Options()};
  /// Ticks the replanning node until it waits at a step boundary (at most `seconds` simulated).
  void TickUntilWaiting(double seconds) {
    const long ticks = std::lround(seconds * config_.control_rate_hz);
    for (long k = 0; k < ticks; ++k) {
      replanning_.Tick();
      Pump();
      if (replanning_.Paused()) return;
    }
  }
  /// What the simulator sent of one tick: the measured state and the controller's status.
  struct Heard {
    rbcp_msgs::robot_state_t state;
    rbcp_msgs::controller_status_t controller;
  };
  Heard Tick() {
    replanning_.Tick();
    Pump();
    const Heard heard{*states_.Latest(), *controllers_.Latest()};
    EXPECT_EQ(heard.state.utime, heard.controller.utime) << "the controller's status beside every state";
    return heard;
  }
  void PublishPlannerFailure(int64_t input_utime) {
    rbcp_msgs::process_status_t f{};
    f.process = "contact_planner";
    f.state = rbcp_msgs::process_status_t::FAILED;
    f.reason = "no_foothold: test";
    f.input_utime = input_utime;
    f.handled = ++handled_;
    lcm_.publish(channels::kStatus, &f);
    Pump();
  }
  /// The planner fails the wait since `boundary`: the robot stops waiting, then ticks (at most
  /// `seconds` simulated) to its next wait; returns the state there.
  Heard FailAndTickToTheNextWait(int64_t boundary, double seconds) {
    PublishPlannerFailure(boundary);
    EXPECT_FALSE(Tick().controller.awaiting_plan);
    TickUntilWaiting(seconds);
    EXPECT_TRUE(replanning_.Paused());
    return Tick();
  }
  int64_t handled_ = 0;
};

TEST_F(SimWorld, ARobotOnAPerceivedTerrainLooksAroundBeforeItsFirstWait) {
  ASSERT_EQ(config_.sensing.look_before_walking_s, 1.0);
  SimNode node(lcm_, execution_, scenario_, config_, Perceived(/*replan=*/true));
  node.status().set_verbose(false);
  PublishMapperUp(lcm_);
  Pump();
  for (int k = 0; k < 1000 && !node.Paused(); ++k) {
    node.Tick();
    Pump();
  }
  ASSERT_TRUE(node.Paused());
  EXPECT_EQ(states_.Latest()->utime, 1000000) << "it waits once it has looked for a second";
  EXPECT_EQ(clouds_.messages.size(), 2u * 10u) << "two cameras at 0.1, 0.2, ..., 1.0 s";
}

TEST_F(SimWorld, WhileTheWorldStandsStillTheStanceOfTheWaitIsCapturedOnce) {
  SimConfig config = config_;
  config.sensing.look_before_walking_s = 0.0;  // it waits at once
  SimNode node(lcm_, execution_, scenario_, config, Perceived(/*replan=*/true));
  node.status().set_verbose(false);
  PublishMapperUp(lcm_);
  Pump();
  const auto tick = [&] {
    node.Tick();
    Pump();
    // A paused world publishes its state every 5 ms of wall time.
    std::this_thread::sleep_for(std::chrono::microseconds(node.Paused() ? 5500 : 0));
  };
  for (int k = 0; k < 20; ++k) tick();
  ASSERT_TRUE(node.Paused());
  ASSERT_EQ(clouds_.messages.size(), 2u) << "the robot waits for its first plan: its stance, captured once";
  EXPECT_EQ(clouds_.messages.front().utime, 0);

  ContactPlan piece = rbcp::test::BuildFlatGroundPlan(robot_, 2, 0.08);
  piece.reaches_goal = false;
  const int64_t start = states_.Latest()->utime;
  const auto plan = transport::ToContactPlanMsg(piece, start, 7, 12345, 1, start);
  lcm_.publish(channels::kContactPlan, &plan);
  Pump();
  for (int k = 0; k < 8000 && (k == 0 || !node.Paused()); ++k) tick();
  ASSERT_TRUE(node.Paused()) << "the robot waits after its first step (a plan on a map: any terrain id)";
  const int64_t boundary = states_.Latest()->utime;
  const std::size_t walking = clouds_.messages.size();
  EXPECT_EQ(walking, 2u * static_cast<std::size_t>(boundary / 100000 + 1)) << "two sensors every 0.1 s";
  for (int k = 0; k < 20; ++k) tick();
  EXPECT_EQ(states_.Latest()->utime, boundary);
  EXPECT_EQ(clouds_.messages.size(), walking) << "nothing new while the world stands still";
}

TEST_F(ReplanningSimNodeTest, WaitsAtEveryStepBoundaryForAPlanFromThatStance) {
  // Standing with no plan: the world stands still and CONTROLLER_STATUS says the robot waits.
  auto state = Tick();
  ASSERT_TRUE(replanning_.Paused());
  for (int k = 0; k < 5; ++k) state = Tick();
  EXPECT_TRUE(state.controller.awaiting_plan);
  EXPECT_EQ(state.state.utime, state.controller.awaiting_since) << "the world stands still while the robot waits";
  EXPECT_EQ(state.controller.plan_seq, 0);

  // A plan of two steps that stops short of the goal, from this wait: taken.
  ContactPlan piece = rbcp::test::BuildFlatGroundPlan(robot_, 2, 0.08);
  piece.reaches_goal = false;
  const auto first = transport::ToContactPlanMsg(piece, state.state.utime, 7, WorldTerrainId(), 1, state.state.utime);
  lcm_.publish(channels::kContactPlan, &first);
  Pump();
  state = Tick();
  EXPECT_FALSE(state.controller.awaiting_plan);
  EXPECT_EQ(state.controller.plan_seq, 1);
  TickUntilWaiting(20.0);
  ASSERT_TRUE(replanning_.Paused()) << "the robot waits after its first step";
  state = Tick();
  EXPECT_EQ(state.controller.steps_done, 1);
  EXPECT_GT(state.controller.awaiting_since, first.start_utime);
  const int64_t boundary = state.controller.awaiting_since;

  // A plan from the stance before that step is stale: dropped, and the robot goes on waiting.
  lcm_.publish(channels::kContactPlan, &first);
  Pump();
  state = Tick();
  EXPECT_EQ(replanning_.StalePlans(), 1);
  EXPECT_TRUE(state.controller.awaiting_plan);
  EXPECT_EQ(state.state.utime, boundary);

  // The planner fails this wait: the robot walks the rest of its plan, then waits again.
  state = FailAndTickToTheNextWait(boundary, 20.0);
  EXPECT_EQ(state.controller.steps_done, 2);
  EXPECT_FALSE(replanning_.Decided()) << "a plan short of the goal is no verdict";

  // Nothing left to walk and the planner fails again: the robot holds its stance for
  // retry_hold_s of simulated time, then asks again.
  const int64_t second_boundary = state.controller.awaiting_since;
  state = FailAndTickToTheNextWait(second_boundary, 2.0);
  EXPECT_GE(state.controller.awaiting_since - second_boundary, 500000);
  EXPECT_EQ(state.controller.steps_done, 2);
  const RobotState measured = transport::FromRobotStateMsg(state.state);
  for (bool c : measured.foot_contact) EXPECT_TRUE(c);

  // max_failed_waits such waits in a row: the run fails, with the reason on STATUS.
  PublishPlannerFailure(state.controller.awaiting_since);
  Tick();
  ASSERT_TRUE(replanning_.Decided());
  EXPECT_FALSE(execution_.Outcome().ok());
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(status_.Latest()->reason.find("no_plan"), std::string::npos) << status_.Latest()->reason;
}

/// The world changes at the events' simulated times: a box added and removed, a push, a new goal.
class EventsSimNodeTest : public SimWorld {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm_.good());
    node_.status().set_verbose(false);
  }
  static SimNodeOptions Options() {
    SimNodeOptions o;
    o.events = ParseWorldEvents(R"(events:
  - {t: 0.2, add_box: {name: crate, size: [0.3, 0.3, 0.1], position: [1.5, 0.0, 0.05], rpy: [0, 0, 0]}}
  - {t: 0.5, push: {force: [0, 80, 0], duration: 0.2}}
  - {t: 0.6, goal: {position: [2.0, 0.5], yaw: 0.3}}
  - {t: 1.0, remove_box: crate}
)", "events.yaml");
    return o;
  }
  void TickTo(double t) {
    while (node_.SimTime() + 1e-9 < t) {
      node_.Tick();
      Pump();
    }
  }
  SimNode node_{lcm_, execution_, scenario_, config_, Options()};
  transport::LatestMessage<rbcp_msgs::plan_request_t> requests_{lcm_, channels::kPlanRequest};
};

TEST_F(EventsSimNodeTest, ChangesTheWorldAtTheEventsTimes) {
  const std::size_t elements = scenario_.terrain.size();
  const int triangles = static_cast<int>(scenario_.terrain_mesh.NumTriangles());
  TickTo(0.19);
  EXPECT_EQ(terrain_.received(), 1);
  EXPECT_EQ(terrain_.Latest()->num_triangles, triangles);
  // The box: in the world, and on TERRAIN at once.
  TickTo(0.21);
  EXPECT_EQ(terrain_.received(), 2);
  EXPECT_EQ(terrain_.Latest()->num_triangles, triangles + 12);
  EXPECT_EQ(execution_.CurrentWorld().terrain.size(), elements + 1);
  // The push moves the standing robot sideways; nothing else does.
  TickTo(0.5);
  const double y0 = states_.Latest()->base_position[1];
  TickTo(0.75);
  const double y1 = states_.Latest()->base_position[1];
  EXPECT_GT(y1 - y0, 0.002) << "pushed along +y with 80 N for 0.2 s";
  // The new goal: a request from the robot's state, with the next id.
  ASSERT_TRUE(requests_.Latest().has_value());
  EXPECT_EQ(requests_.Latest()->request_id, 1);
  EXPECT_FALSE(requests_.Latest()->use_start);
  EXPECT_DOUBLE_EQ(requests_.Latest()->goal_position[0], 2.0);
  EXPECT_DOUBLE_EQ(requests_.Latest()->goal_position[1], 0.5);
  EXPECT_DOUBLE_EQ(requests_.Latest()->goal_yaw, 0.3);
  // The box is gone again.
  TickTo(1.01);
  EXPECT_EQ(terrain_.received(), 4);  // also the periodic one at 1 s
  EXPECT_EQ(terrain_.Latest()->num_triangles, triangles);
  EXPECT_EQ(execution_.CurrentWorld().terrain.size(), elements);
  EXPECT_FALSE(execution_.Decided());
}

TEST(WorldEvents, ReadsStrictlyWithClearErrors) {
  const std::vector<WorldEvent> events = ParseWorldEvents(R"(events:
  - {t: 3.0, remove_box: b}
  - {t: 1.0, add_box: {name: b, size: [1, 1, 0.1], position: [0, 0, 0.05], rpy: [0, 0, 0]}}
  - {t: 2.0, push: {force: [10, 0, 0], duration: 0.5}}
)", "e.yaml");
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].kind, WorldEvent::Kind::kAddBox);  // in time order
  EXPECT_EQ(events[1].Describe(), "push the base with 10.0 N (10.00, 0.00, 0.00) for 0.50 s");
  EXPECT_EQ(events[2].Describe(), "remove box 'b'");
  const auto error = [](const std::string& text) {
    try {
      ParseWorldEvents(text, "e.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("events: [{t: 1, remove_box: nope}]"),
            "e.yaml: box 'nope' is removed at 1.00 s, but it is not in the world then (never added, or removed before)");
  EXPECT_EQ(error("events: [{t: 1, push: {force: [1, 0, 0], duration: 0}}]"),
            "e.yaml: events[0]: push: 'duration': expected a duration in (0, 10] s, got 0.000");
  EXPECT_EQ(error("events: [{t: 1, jump: 2}]"),
            "e.yaml: events[0]: 'jump': unknown event (expected add_box, remove_box, push or goal)");
  EXPECT_EQ(error("events: [{t: 1, push: {force: [1, 0, 0], duration: 1}, goal: {position: [0, 0], yaw: 0}}]"),
            "e.yaml: events[0]: expected t and exactly one of add_box, remove_box, push or goal, got 2 other keys");
  EXPECT_EQ(error("events: [{t: 2, add_box: {name: b, size: [1, 1, 1], position: [0, 0, 0], rpy: [0, 0, 0]}}, "
                  "{t: 1, remove_box: b}]"),
            "e.yaml: box 'b' is removed at 1.00 s, but it is not in the world then (never added, or removed before)");
  EXPECT_EQ(error("events: [{t: -1, goal: {position: [0, 0], yaw: 0}}]"),
            "e.yaml: events[0]: 't': expected a simulated time in [0, 1000000] s, got -1.000");
  // Bounds: no box far away or huge, no push beyond reason, no box removed twice, a bounded world.
  EXPECT_EQ(error("events: [{t: 1, add_box: {name: b, size: [1, 1, 1], position: [1e300, 0, 0], rpy: [0, 0, 0]}}]"),
            "e.yaml: events[0]: add_box: 'position': expected a point within 1000 m of the origin, got "
            "(" + FixedNumber(1e300, 2) + ", 0.00, 0.00)");
  EXPECT_EQ(error("events: [{t: 1, push: {force: [1e300, 0, 0], duration: 1}}]"),
            "e.yaml: events[0]: push: 'force': expected at most 2000 N, got (" + FixedNumber(1e300, 2) + ", 0.00, 0.00)");
  EXPECT_EQ(error("events: [{t: 1, add_box: {name: b, size: [1, 1, 1], position: [0, 0, 0], rpy: [0, 0, 0]}}, "
                  "{t: 2, remove_box: b}, {t: 3, remove_box: b}]"),
            "e.yaml: box 'b' is removed at 3.00 s, but it is not in the world then (never added, or removed before)");
  std::string many = "events: [";
  for (int i = 0; i < 201; ++i) {
    many += (i ? ", " : "") + std::string("{t: 1, add_box: {name: b") + std::to_string(i) +
            ", size: [0.1, 0.1, 0.1], position: [0, 0, 0], rpy: [0, 0, 0]}}";
  }
  EXPECT_EQ(error(many + "]"), "e.yaml: 201 boxes of the events would be in the world at 1.00 s, at most 200");
}

}  // namespace
}  // namespace rbcp::sim
