#pragma once
/// The simulator as a process (anymal_sim): it is the world. It publishes TERRAIN (at start and
/// again every terrain_period_s of simulated time, so a late process gets it), ROBOT_STATE at the
/// control rate of simulated time, and STATUS; it takes CONTACT_PLAN and has the onboard
/// controller walk it. Before the first plan the robot stands at the scenario's start.
///
/// STATUS: ALIVE while standing without a plan, BUSY while walking one ("step 3/40"), then OK
/// ("goal reached: ...") or FAILED with the simulator's verdict ("fall at 12.3 s, step 7: ...").

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <string>

#include "rbcp/scenario/scenario.h"
#include "rbcp/sim/plan_execution.h"
#include "rbcp/sim/sim_config.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/contact_plan_t.hpp"

namespace rbcp::sim {

/// One line: "goal reached in 41.2 s of simulated time, 40 steps, max torque 71% of the limit"
/// or "fall at 12.30 s, step 7 (LF): LF_THIGH touches the terrain".
std::string OutcomeSummary(const ExecutionOutcome& outcome);

class SimNode {
 public:
  static constexpr const char* kProcessName = "anymal_sim";

  /// Stands the robot at the scenario's start. `execution` must outlive the node.
  SimNode(lcm::LCM& lcm, PlanExecution& execution, const Scenario& scenario, const SimConfig& config);

  /// One control tick of simulated time: takes the newest CONTACT_PLAN, advances the world,
  /// publishes ROBOT_STATE and, when due, TERRAIN; reports a decided outcome once on STATUS.
  void Tick();
  /// Republishes the current STATUS.
  void Heartbeat();

  double SimTime() const { return execution_.Time(); }
  /// True once a plan was walked to its outcome (and no newer plan is running).
  bool Decided() const { return execution_.Decided() && plans_ > 0; }
  int Plans() const { return plans_; }
  transport::StatusReporter& status() { return status_; }

 private:
  int64_t Utime() const;
  void PublishTerrain();

  lcm::LCM& lcm_;
  PlanExecution& execution_;
  Scenario scenario_;
  SimConfig config_;
  transport::StatusReporter status_;
  transport::LatestMessage<rbcp_msgs::contact_plan_t> plans_in_;
  double next_terrain_s_ = 0.0;
  int plans_ = 0;
  bool reported_ = false;
  int64_t plan_utime_ = 0;
  int last_step_reported_ = -1;
};

}  // namespace rbcp::sim
