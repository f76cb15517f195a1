#pragma once
/// The root planner process: PLAN_REQUEST, ROBOT_STATE, TERRAIN and AFFORDANCES in; ROOT_PATH
/// and STATUS out. Callbacks only keep the latest messages; Step() does the work.

#include <lcm/lcm-cpp.hpp>

#include <optional>
#include <string>
#include <vector>

#include "rbcp/nodes/world_input.h"
#include "rbcp/root_planner/root_planner.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::nodes {

struct RootPlannerNodeOptions {
  std::string request_channel = channels::kPlanRequest;
  std::string robot_state_channel = channels::kRobotState;
  std::string terrain_channel = channels::kTerrain;
  std::string affordances_channel = channels::kAffordances;
  std::string root_path_channel = channels::kRootPath;
  std::string status_channel = channels::kStatus;
  double default_time_budget_s = 2.0;  ///< used when a request gives none [s]
};

class RootPlannerNode {
 public:
  static constexpr const char* kProcessName = "root_planner";

  RootPlannerNode(lcm::LCM& lcm, const RobotModel& robot, RootPlannerConfig config, RootPlannerNodeOptions options = {});

  /// Takes the newest inputs; when a plan request is pending and the terrain and its surfaces
  /// are known, plans and publishes ROOT_PATH (or FAILED with the reason on STATUS). A request
  /// with use_start = false starts from the latest ROBOT_STATE. Returns true if it planned or
  /// rejected an input.
  bool Step();
  void Heartbeat();

  transport::StatusReporter& status() { return status_; }
  /// The latest answer (empty path when the latest request failed).
  const std::optional<RootPlanResult>& last_result() const { return last_result_; }

 private:
  /// Takes new terrain / surfaces / request; returns a reason if an input was rejected.
  std::optional<std::string> TakeInputs();
  void Plan(const rbcp_msgs::plan_request_t& request);
  int64_t Now() const;

  lcm::LCM& lcm_;
  RootPlannerNodeOptions options_;
  RootPlanner planner_;
  transport::LatestMessage<rbcp_msgs::plan_request_t> request_;
  transport::LatestMessage<rbcp_msgs::robot_state_t> robot_state_;
  WorldInput world_;
  transport::StatusReporter status_;

  std::optional<rbcp_msgs::plan_request_t> pending_;
  std::optional<RootPlanResult> last_result_;
  int64_t latest_utime_ = 0;
};

/// The LCM message of a planned path: samples every time step, orientation from the yaw.
rbcp_msgs::root_path_t ToRootPathMsg(const RootPlanResult& result, int64_t utime, int64_t request_id);

}  // namespace rbcp::nodes
