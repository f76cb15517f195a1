#pragma once
/// A run of the replanning loop as its LCM traffic shows it: the robot's states (ROBOT_STATE), the
/// controller's progress (CONTROLLER_STATUS) and the plans (CONTACT_PLAN), in the order they were
/// received and with their receive times. Fed live (scenario_publisher) or from a recorded log
/// (run_log), it gives the plan the robot walked, the replans and their latency, and the robot's
/// trace.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/contact_plan.h"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"

namespace rbcp::nodes {

class RunRecord {
 public:
  /// A sample of the trace: the measured state and the controller's status last heard with it.
  struct TraceEntry {
    rbcp_msgs::robot_state_t state;
    std::optional<rbcp_msgs::controller_status_t> controller;
  };

  /// `trace_rate_hz`: ROBOT_STATE is kept for the trace at this rate of simulated time.
  explicit RunRecord(double trace_rate_hz = 20.0);

  /// `receive_us`: when the message was received [us] (any clock, the same for every kind).
  void OnRobotState(int64_t receive_us, const rbcp_msgs::robot_state_t& msg);
  void OnControllerStatus(int64_t receive_us, const rbcp_msgs::controller_status_t& msg);
  /// Throws InputError for a malformed plan.
  void OnContactPlan(int64_t receive_us, const rbcp_msgs::contact_plan_t& msg);

  int Plans() const { return plans_; }
  int GoalPlans() const { return goal_plans_; }
  /// The latency of each replan [ms]: from the first receipt of the ROBOT_STATE a plan starts from
  /// (a state of the robot's wait at a step boundary) to the receipt of that plan. The first plan
  /// (which also waits for the world and the root path) is not a replan.
  const std::vector<double>& LatenciesMs() const { return latencies_ms_; }
  /// For each latency of LatenciesMs(), the simulated time [s] of the state that replan started from.
  const std::vector<double>& LatencyTimesS() const { return latency_times_s_; }
  /// Waits of the robot that got no plan (the planner failed or did not answer in time).
  int UnansweredWaits() const { return unanswered_ + (wait_ && !wait_->answered ? 1 : 0); }
  const std::optional<rbcp_msgs::robot_state_t>& Latest() const { return latest_; }
  const std::optional<rbcp_msgs::controller_status_t>& LatestController() const { return latest_controller_; }
  /// ROBOT_STATE every 1 / trace_rate_hz of simulated time.
  const std::vector<TraceEntry>& Trace() const { return trace_; }
  /// The largest distance of the measured base from the controller's reference over the run [m].
  double MaxBaseErrorM() const { return max_base_error_m_; }
  /// The pipeline's start-up [s, wall clock]: from the first message received until the robot
  /// first walks after the first plan arrived (a CONTROLLER_STATUS that no longer waits). Until
  /// then, the time so far. It holds the world's extraction, the root path and the first plan,
  /// and a first plan that failed and was planned again along another guide.
  double StartupWallS() const;
  /// The walk's wall time so far [s]: from the end of the start-up to the latest message.
  double WalkWallS() const;
  /// The wall time [s] the robot stood at a step boundary waiting for a plan during the walk: the
  /// time from each CONTROLLER_STATUS that says it waits (awaiting_plan) to the next one received.
  double WaitingWallS() const { return 1e-6 * static_cast<double>(waiting_us_); }
  /// WaitingWallS() over WalkWallS(): the share of the walk the robot stood waiting for a plan
  /// (0 before the walk began).
  double WaitingShare() const;

  /// The plan the robot walked: the first walked plan's first state, then the states of each plan
  /// for the steps walked while it was the robot's plan (CONTROLLER_STATUS's plan_seq and
  /// steps_done). Untimed: each piece was timed from its own start.
  /// Throws InputError when a walked plan was not received; with `missing`, such a plan's steps
  /// are left out instead (the plan then jumps there) and *missing names each one.
  ContactPlan ExecutedPlan(std::vector<std::string>* missing = nullptr) const;

 private:
  /// Keeps the first and the latest receive time.
  void Received(int64_t receive_us);

  struct Wait {
    int64_t since = 0;
    std::map<int64_t, int64_t> first_receipt;  // state utime -> first receive time [us]
    bool answered = false;
  };
  struct Segment {
    int64_t plan_seq = 0;
    int steps_at_start = 0;
  };
  double trace_period_us_;
  int plans_ = 0;
  int goal_plans_ = 0;
  int unanswered_ = 0;
  std::vector<double> latencies_ms_;
  std::vector<double> latency_times_s_;
  std::optional<Wait> wait_;
  std::optional<rbcp_msgs::robot_state_t> latest_;
  std::optional<int64_t> latest_receive_us_;
  std::optional<rbcp_msgs::controller_status_t> latest_controller_;
  double max_base_error_m_ = 0.0;
  std::optional<int64_t> first_receive_us_, last_receive_us_;
  std::optional<int64_t> walk_start_us_;  // the end of the start-up (StartupWallS)
  std::optional<int64_t> waiting_since_receive_us_;  // the receipt of the latest status while waiting
  int64_t waiting_us_ = 0;
  std::vector<TraceEntry> trace_;
  std::map<int64_t, ContactPlan> plans_by_seq_;
  std::vector<Segment> segments_;
};

/// The p-quantile (0..1) of `values` with linear interpolation; 0 when empty.
double Percentile(std::vector<double> values, double p);

}  // namespace rbcp::nodes
