// The simulator's node over memq://: what it publishes, a plan walked to its verdict on STATUS,
// and a malformed plan answered with FAILED while the world goes on.
#include "rbcp/sim/sim_node.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "flat_ground_plan.h"
#include "rbcp/controller/controller_config.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::sim {
namespace {

using rbcp::test::ConfigDir;
using rbcp::test::ScenarioPath;

class SimNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm_.good());
    node_.status().set_verbose(false);
  }
  void Pump() {
    while (lcm_.handleTimeout(0) > 0) {
    }
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

  RobotModel robot_ = RobotModel::LoadDefault(ConfigDir());
  SimConfig config_ = SimConfig::LoadFile(ConfigDir() + "/sim.yaml");
  Scenario scenario_ = LoadScenario(ScenarioPath("flat_ground"));
  PlanExecution execution_{robot_, ConfigDir() + "/robots/anymal_b.urdf", scenario_, config_,
                           ControllerConfig::LoadFile(ConfigDir() + "/controller.yaml")};
  lcm::LCM lcm_{"memq://"};
  SimNode node_{lcm_, execution_, scenario_, config_};
  transport::LatestMessage<rbcp_msgs::robot_state_t> states_{lcm_, channels::kRobotState};
  transport::LatestMessage<rbcp_msgs::terrain_mesh_t> terrain_{lcm_, channels::kTerrain};
  transport::LatestMessage<rbcp_msgs::process_status_t> status_{lcm_, channels::kStatus};
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

TEST_F(SimNodeTest, WalksAPlanAndReportsTheVerdict) {
  TickFor(0.3, [] { return false; });
  const auto plan = transport::ToContactPlanMsg(rbcp::test::BuildFlatGroundPlan(robot_, 2, 0.08), 0, 7);
  lcm_.publish(channels::kContactPlan, &plan);
  Pump();
  TickFor(20.0, [&] { return node_.Decided(); });
  ASSERT_TRUE(node_.Decided());
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK) << status_.Latest()->reason;
  EXPECT_NE(status_.Latest()->reason.find("goal reached"), std::string::npos);
}

TEST_F(SimNodeTest, AMalformedPlanIsRejectedAndTheRobotKeepsStanding) {
  auto plan = transport::ToContactPlanMsg(rbcp::test::BuildFlatGroundPlan(robot_, 2, 0.08), 0, 7);
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

}  // namespace
}  // namespace rbcp::sim
