#pragma once
/// The simulator as a process (anymal_sim): it is the world. It publishes TERRAIN (at start and
/// again every terrain_period_s of simulated time, so a late process gets it), ROBOT_STATE at the
/// control rate of simulated time with the onboard controller's CONTROLLER_STATUS beside it (same
/// utime), and STATUS; it takes CONTACT_PLAN and has the onboard controller walk it. Before the
/// first plan the robot stands at the scenario's start.
///
/// STATUS: ALIVE while standing without a plan, BUSY while walking one ("step 3/40"), then OK
/// ("goal reached: ...") or FAILED with the simulator's verdict ("fall at 12.3 s, step 7: ...").
///
/// Replanning (SimNodeOptions::replan): the controller stops at every step boundary and
/// CONTROLLER_STATUS says so (awaiting_plan, awaiting_since). It takes only a CONTACT_PLAN that starts
/// from a state of that wait (start_utime >= awaiting_since); older plans are stale and dropped.
/// When the contact planner answers that wait with FAILED, or no plan comes within
/// await_timeout_s of wall time, the robot goes on with the rest of its current plan; with none
/// left it holds its stance for retry_hold_s of simulated time and asks again; after
/// max_failed_waits such waits in a row the run fails ("no_plan"). With
/// pause_while_awaiting (runs faster than real time) the world stands still during the wait, so a
/// run does not depend on how fast the planners answer.
///
/// What the planners plan on (SimNodeOptions::terrain). Ground truth: the true terrain goes out on
/// TERRAIN and no sensor runs. Perceived: the depth sensors (SimConfig::sensing, depth_sensor.h)
/// capture every 1/rate_hz of simulated time at a control tick, from the state that tick's
/// ROBOT_STATE carries, and POINT_CLOUD goes out just before it with the same utime (terrain_mapper
/// maps them onto TERRAIN); the true terrain goes out on TERRAIN_TRUTH, and plans are not judged
/// stale by the true terrain they cannot know. While the world stands still (Paused) the state of
/// the wait is captured once, when a capture is due then (the robot's first stance, at 0 s). The world
/// starts once the mapper's STATUS is heard (SimNodeOptions::mapper).
///
/// The world changes at the events' simulated times (SimNodeOptions::events): a box added or
/// removed is in the physics, the judge's and the controller's terrain at once and TERRAIN goes
/// out at once; a push is a force on the base for its duration; a new goal is a PLAN_REQUEST
/// (the latest request's id + 1, from the robot's state, its seed and budget), repeated every
/// second like the operator's. A plan made before the world last changed, or for an earlier
/// request than the latest, is stale: it is dropped, and the robot does not go on with the rest
/// of one when no new plan comes (it holds its stance).

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/scenario/scenario.h"
#include "rbcp/sim/depth_sensor.h"
#include "rbcp/sim/plan_execution.h"
#include "rbcp/sim/sim_config.h"
#include "rbcp/sim/world_events.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/plan_requests.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"

namespace rbcp::sim {

/// One line: "goal reached in 41.2 s of simulated time, 40 steps, max torque 71% of the limit"
/// or "fall at 12.30 s, step 7 (LF): LF_THIGH touches the terrain".
std::string OutcomeSummary(const ExecutionOutcome& outcome);

/// What the planners plan on.
enum class TerrainSource {
  kGroundTruth,  ///< the simulator's true terrain, on TERRAIN
  kPerceived,    ///< the map terrain_mapper makes of the depth sensors' POINT_CLOUD
};
/// "ground_truth", "perceived".
const EnumNames<TerrainSource>& TerrainSourceNames();

struct SimNodeOptions {
  TerrainSource terrain = TerrainSource::kGroundTruth;
  bool replan = false;               ///< wait at every step boundary for a plan from that stance
  bool pause_while_awaiting = true;  ///< replan: the world stands still while the robot waits
  double await_timeout_s = 15.0;     ///< [s, wall clock] replan: longest wait for an answer
  double retry_hold_s = 0.5;         ///< [s, simulated] replan: hold before asking again, nothing left to walk
  int max_failed_waits = 20;         ///< replan: waits in a row with no plan and nothing left to walk before the run fails
  std::string contact_planner = "contact_planner";  ///< process whose FAILED status ends a wait
  /// Perceived terrain: the process the clouds are for. The world starts once its STATUS is heard,
  /// so that no cloud of the robot's first look goes out before it listens.
  std::string mapper = "terrain_mapper";
  /// Scripted changes of the world (world_events.h), applied at their simulated times.
  std::vector<WorldEvent> events;
};

class SimNode {
 public:
  static constexpr const char* kProcessName = "anymal_sim";

  /// Stands the robot at the scenario's start. `execution` must outlive the node.
  SimNode(lcm::LCM& lcm, PlanExecution& execution, const Scenario& scenario, const SimConfig& config,
          SimNodeOptions options = {});

  /// One control tick of simulated time: takes the newest CONTACT_PLAN, advances the world,
  /// publishes ROBOT_STATE, when due POINT_CLOUD and TERRAIN (in parts when large; a message too
  /// large to send is reported FAILED on STATUS with its size and the bound); reports a decided
  /// outcome once on STATUS.
  void Tick();
  /// Republishes the current STATUS.
  void Heartbeat();

  double SimTime() const { return execution_.Time(); }
  /// Replanning: the robot waits at a step boundary and the world stands still (no physics).
  bool Paused() const { return options_.replan && options_.pause_while_awaiting && awaiting_since_.has_value(); }
  int StalePlans() const { return stale_plans_; }
  /// True once a plan was walked to its outcome (and no newer plan is running).
  bool Decided() const { return execution_.Decided() && (plans_ > 0 || options_.replan); }
  int Plans() const { return plans_; }
  /// POINT_CLOUD messages published so far.
  long PointClouds() const { return point_clouds_; }
  transport::StatusReporter& status() { return status_; }

 private:
  int64_t Utime() const;
  void PublishTerrain();
  void TakePlan(const rbcp_msgs::contact_plan_t& msg);
  void UpdateWait();
  /// Publishes the tick's POINT_CLOUD captures (when due), then CONTROLLER_STATUS and ROBOT_STATE.
  void PublishState();
  /// The depth sensors' captures due at `state` (the tick's state, `state_msg` its ROBOT_STATE),
  /// on POINT_CLOUD with that message's utime and base pose.
  void PublishClouds(const RobotState& state, const rbcp_msgs::robot_state_t& state_msg);
  /// Applies the events due by now; ends a push that is over.
  void ApplyEvents();
  /// The terrain as the events due at one tick change it: applied once, after all of them.
  struct TerrainEdit {
    std::vector<TerrainElement> terrain;
    std::vector<std::string> names;  ///< per element: the event box's name, "" for the scenario's
    bool changed = false;
  };
  /// Applies a push or a goal at once; a box added or removed goes into `edit`.
  void Apply(const WorldEvent& event, TerrainEdit& edit);

  lcm::LCM& lcm_;
  PlanExecution& execution_;
  Scenario scenario_;
  SimConfig config_;
  transport::StatusReporter status_;
  transport::MessagePublisher publisher_;  ///< TERRAIN and POINT_CLOUD, in parts when large
  SensorRig sensors_;
  long point_clouds_ = 0;
  SimNodeOptions options_;
  transport::LatestMessage<rbcp_msgs::contact_plan_t> plans_in_;
  transport::LatestMessage<rbcp_msgs::process_status_t> planner_failures_;
  transport::LatestMessage<rbcp_msgs::process_status_t> mapper_status_;  ///< perceived: the mapper's STATUS
  bool mapper_heard_ = false;
  transport::LatestMessage<rbcp_msgs::plan_request_t> requests_;
  transport::RequestHistory requests_taken_;  ///< the goal requests seen (or sent), the goal last
  std::optional<rbcp_msgs::plan_request_t> own_request_;     ///< the latest goal an event sent, repeated
  std::chrono::steady_clock::time_point own_request_wall_;
  std::size_t next_event_ = 0;
  std::vector<std::string> element_names_;  ///< per terrain element: the event box's name, "" for the scenario's
  double push_until_s_ = -1.0;              ///< a push ends at this simulated time (< 0: none)
  int64_t terrain_id_ = 0;                  ///< transport::TerrainId of the world's terrain now
  int64_t walked_plan_terrain_id_ = 0;      ///< the terrain the plan being walked was made on
  std::optional<int64_t> awaiting_since_;  // replan: utime the current wait began
  std::chrono::steady_clock::time_point await_wall_start_;
  double hold_until_s_ = 0.0;              // replan: no new wait before this simulated time
  int64_t plan_seq_ = 0;
  int64_t plan_request_id_ = 0;  ///< request_id of the plan being walked
  int stale_plans_ = 0;
  int failed_waits_ = 0;  // replan: waits in a row that ended with no plan and nothing to walk
  std::chrono::steady_clock::time_point last_state_wall_;
  std::chrono::steady_clock::time_point last_terrain_wall_;
  int64_t answered_utime_ = -1;            // replan: utime of the last plan taken or wait given up
  double next_terrain_s_ = 0.0;
  int plans_ = 0;
  bool reported_ = false;
  int64_t plan_utime_ = 0;
  int last_step_reported_ = -1;
};

}  // namespace rbcp::sim
