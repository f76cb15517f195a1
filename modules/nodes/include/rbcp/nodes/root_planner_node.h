#pragma once
/// The root planner process: PLAN_REQUEST, ROBOT_STATE, TERRAIN and AFFORDANCES in; ROOT_PATH
/// and STATUS out. Callbacks only keep the latest messages; Step() does the work.

#include <lcm/lcm-cpp.hpp>

#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "rbcp/nodes/world_input.h"
#include "rbcp/root_planner/root_planner.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/sim_clock.h"
#include "rbcp/transport/plan_requests.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::nodes {

struct RootPlannerNodeOptions {
  std::string request_channel = channels::kPlanRequest;
  std::string robot_state_channel = channels::kRobotState;
  std::string controller_status_channel = channels::kControllerStatus;
  std::string terrain_channel = channels::kTerrain;
  std::string affordances_channel = channels::kAffordances;
  std::string root_path_channel = channels::kRootPath;
  std::string status_channel = channels::kStatus;
  double default_time_budget_s = 2.0;  ///< used when a request gives none [s]
  double max_time_budget_s = 60.0;     ///< a request asking for more is rejected [s]
  /// Replan the current request from the measured base when the robot, waiting at a step
  /// boundary, stands farther than this from the path (horizontally) [m]; the body's own shifts
  /// for its swings stay within the contact planner's 0.16 m.
  double replan_path_offset_m = 0.3;
  /// The terrain is a map that grows as the robot walks (terrain_mapper; `--terrain perceived`):
  /// a goal the map does not show yet is planned toward, to the first of the known terrain's
  /// standing positions nearest it that has a path (RootPlanner::GoalsToward; the path says it
  /// does not reach the goal), and a new map is planned on again while the robot waits at a step
  /// boundary (also after a request found no path on the map before) unless the path the robot
  /// follows holds on it (KeepPathOnNewMap). A path kept, or kept by a replan that fails, is sent
  /// again as the path on the new map. Requests and replans are planned on the map of a wait of
  /// the robot (TERRAIN utime >= awaiting_since), so that a path depends on the clouds up to the
  /// wait and not on when the request or the maps came.
  bool partial_map = false;
  GoalsTowardOptions partial_goals;      ///< partial_map: where to plan towards a goal the map does not show
  /// partial_map: a path short of the goal is planned again on a new map when the map shows a
  /// standing position this much nearer the goal than the path's end [m]
  double partial_replan_gain_m = 0.5;
};

class RootPlannerNode {
 public:
  static constexpr const char* kProcessName = "root_planner";

  RootPlannerNode(lcm::LCM& lcm, const RobotModel& robot, RootPlannerConfig config, RootPlannerNodeOptions options = {});

  /// Takes the newest inputs; when a plan request is pending and the terrain and its surfaces
  /// are known, plans and publishes ROOT_PATH (or FAILED with the reason on STATUS). A request
  /// with use_start = false starts from the latest ROBOT_STATE. Once a path is out, the request
  /// is planned again from the measured base (same request_id and seed) when the terrain or its
  /// surfaces change, and when the robot waits at a step boundary more than
  /// replan_path_offset_m from the path. When the contact planner reports FAILED (no foothold, or
  /// out of its budget) while the robot waits, the request is planned again from the measured
  /// base with the next guide seed (GuideSeed), at most RootPlannerConfig::guide_retries times
  /// while the robot stands in one stance (the same steps_done). Request ids identify requests,
  /// they are not ordered: a request unlike the ones taken before (another id, start, goal or
  /// seed) is new work, whatever its id; a late repeat of one superseded since is ignored. A repeat of the request last taken (the operator
  /// repeats it when an answer got lost, or for a restarted planner) is answered again: its path
  /// once more, or its failure. A request to start more than replan_path_offset_m from where the
  /// robot stands is planned from the robot. A request waiting for the world or the robot's state
  /// is answered ALIVE (idle) with what it waits for. Returns true if it planned, answered or rejected an
  /// input.
  bool Step();
  /// Republishes STATUS, and the current ROOT_PATH unchanged (for a contact planner started
  /// after it went out).
  void Heartbeat();

  transport::StatusReporter& status() { return status_; }
  /// The latest answer (empty path when the latest request failed).
  const std::optional<RootPlanResult>& last_result() const { return last_result_; }

 private:
  /// Takes new terrain / surfaces / request; returns a reason if an input was rejected.
  std::optional<RejectedInput> TakeInputs();
  /// Plans `request` (`why`: the reason of a new path, if any); `replan`: a new path for the
  /// request the robot already follows a path of (ReplanReason).
  void Plan(const rbcp_msgs::plan_request_t& request, const std::string& why, bool replan);
  /// Publishes ALIVE with `what` the pending request waits for, once per change; true if it did.
  bool ReportWaiting(const std::string& what);
  /// The answer to the request last taken, again: its path, or its failure.
  void AnswerAgain();
  /// Plan() for the request last taken, keeping its failure for AnswerAgain().
  void PlanHandled(const rbcp_msgs::plan_request_t& request, const std::string& why, bool replan = false);
  /// The horizontal distance of the measured base from the request's start; nullopt without a
  /// finite measured base.
  std::optional<double> DistanceFromStart(const rbcp_msgs::plan_request_t& request) const;
  /// Whether the robot has not stepped yet and stands within replan_path_offset_m of the
  /// request's start.
  bool StandsAtStart(const rbcp_msgs::plan_request_t& request) const;
  /// Why the current request needs a new path; nullopt when it does not.
  std::optional<std::string> ReplanReason(bool world_changed);
  /// partial_map, at a wait on a new map: whether the path the robot follows goes on (the rest
  /// of it satisfies the reachability condition on the new map, and it reaches the goal or the
  /// map shows neither the goal nor a way partial_replan_gain_m nearer it, and the robot is not at
  /// its end); if so it is sent again as the path on this map.
  bool KeepPathOnNewMap(const rbcp_msgs::robot_state_t& state);
  /// partial_map: the robot waits at a step boundary and the map of that wait (or a later one) is
  /// here: a new request is planned only then.
  bool WaitsOnItsMap() const;
  int64_t Now() const;

  lcm::LCM& lcm_;
  RootPlannerNodeOptions options_;
  RootPlanner planner_;
  transport::LatestMessage<rbcp_msgs::plan_request_t> request_;
  transport::LatestMessage<rbcp_msgs::robot_state_t> robot_state_;
  transport::LatestMessage<rbcp_msgs::controller_status_t> controller_;
  /// The contact planner's latest FAILED STATUS of a planning query (no foothold, out of budget).
  transport::LatestMessage<rbcp_msgs::process_status_t> contact_failure_;
  WorldInput world_;
  transport::StatusReporter status_;

  transport::RequestHistory requests_taken_;
  std::optional<rbcp_msgs::plan_request_t> pending_;
  std::optional<rbcp_msgs::plan_request_t> handled_;  ///< the latest request taken (repeats of it are answered again)
  bool repeat_due_ = false;                           ///< a repeat of handled_ came: answer it again
  std::optional<std::string> handled_failure_;        ///< why handled_ has no path, if it has none
  std::string waiting_for_;                           ///< what the pending request waits for, as last reported
  std::optional<rbcp_msgs::plan_request_t> active_;  ///< the request of the current path
  std::optional<rbcp_msgs::root_path_t> published_;  ///< the current path, republished by Heartbeat()
  std::optional<int64_t> checked_wait_;              ///< awaiting_since of the last wait checked
  std::vector<Eigen::Vector2d> visited_;  ///< partial_map: where the robot stood when planned for, this goal
  std::vector<Eigen::Vector2d> dead_ends_;  ///< partial_map: where the map showed no way nearer this goal
  bool exploring_ = false;                ///< partial_map: the last plan goes to an edge of the map
  bool world_changed_ = false;                       ///< a new terrain or surfaces no replan check has seen
  bool terrain_replan_due_ = false;                  ///< the terrain changed: replan at the next wait
  std::optional<RootPlanResult> last_result_;
  bool last_reaches_goal_ = true;  ///< partial_map: the current path ends at the request's goal
  transport::SimClock clock_;  ///< the simulated time heard of (message utimes)
  int guide_ = 0;  ///< the active request's guide: its paths use GuideSeed(seed, guide_)
  int guides_this_stance_ = 0;  ///< guides planned since the robot last stepped
  std::optional<int32_t> guide_stance_;  ///< CONTROLLER_STATUS steps_done when they were counted
  /// (pid, handled) of the contact planner's last failure acted on.
  std::optional<std::pair<int32_t, int64_t>> failure_acted_;
};

/// The LCM message of a path planned on the terrain `terrain_id`: samples every time step,
/// orientation from the yaw.
rbcp_msgs::root_path_t ToRootPathMsg(const RootPlanResult& result, int64_t utime, int64_t request_id,
                                     int64_t terrain_id, bool reaches_goal = true);

}  // namespace rbcp::nodes
