#include "rbcp/nodes/run_record.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rbcp/core/error.h"
#include "rbcp/transport/convert.h"

namespace rbcp::nodes {
namespace {

/// Receive times kept per wait (a wait with the world standing still repeats one utime).
constexpr std::size_t kMaxStatesPerWait = 4096;

}  // namespace

RunRecord::RunRecord(double trace_rate_hz) : trace_period_us_(trace_rate_hz > 0.0 ? 1e6 / trace_rate_hz : 0.0) {}

void RunRecord::Received(int64_t receive_us) {
  if (!first_receive_us_) first_receive_us_ = receive_us;
  last_receive_us_ = std::max(last_receive_us_.value_or(receive_us), receive_us);
}

double RunRecord::StartupWallS() const {
  if (!first_receive_us_) return 0.0;
  return 1e-6 * static_cast<double>(walk_start_us_.value_or(*last_receive_us_) - *first_receive_us_);
}

double RunRecord::WalkWallS() const {
  return walk_start_us_ ? 1e-6 * static_cast<double>(*last_receive_us_ - *walk_start_us_) : 0.0;
}

double RunRecord::WaitingShare() const {
  const double walk_s = WalkWallS();
  return walk_s > 0.0 ? std::min(1.0, WaitingWallS() / walk_s) : 0.0;
}

void RunRecord::OnRobotState(int64_t receive_us, const rbcp_msgs::robot_state_t& msg) {
  Received(receive_us);
  const bool waiting = wait_ && latest_controller_ && latest_controller_->awaiting_plan &&
                       latest_controller_->awaiting_since == wait_->since && msg.utime >= wait_->since;
  if (waiting && wait_->first_receipt.size() < kMaxStatesPerWait) wait_->first_receipt.emplace(msg.utime, receive_us);
  if (trace_.empty() || static_cast<double>(msg.utime - trace_.back().state.utime) >= trace_period_us_ - 0.5) {
    trace_.push_back({msg, latest_controller_});
  }
  latest_ = msg;
  latest_receive_us_ = receive_us;
}

void RunRecord::OnControllerStatus(int64_t receive_us, const rbcp_msgs::controller_status_t& msg) {
  Received(receive_us);
  if (walk_start_us_ && waiting_since_receive_us_ && receive_us > *waiting_since_receive_us_) {
    waiting_us_ += receive_us - *waiting_since_receive_us_;
  }
  waiting_since_receive_us_.reset();
  if (!walk_start_us_ && plans_ > 0 && !msg.awaiting_plan) walk_start_us_ = receive_us;
  if (msg.awaiting_plan) waiting_since_receive_us_ = receive_us;
  if (msg.awaiting_plan && (!wait_ || wait_->since != msg.awaiting_since)) {
    if (wait_ && !wait_->answered) unanswered_ += 1;
    wait_ = Wait{msg.awaiting_since, {}, false};
    // The state of the wait may have come just before the status that announces it.
    if (latest_ && latest_->utime >= msg.awaiting_since) wait_->first_receipt.emplace(latest_->utime, *latest_receive_us_);
  }
  if (msg.plan_seq > 0 && (segments_.empty() || segments_.back().plan_seq != msg.plan_seq)) {
    segments_.push_back({msg.plan_seq, msg.steps_done});
  }
  if (std::isfinite(msg.base_error)) max_base_error_m_ = std::max(max_base_error_m_, msg.base_error);
  if (!trace_.empty() && trace_.back().state.utime == msg.utime) trace_.back().controller = msg;
  latest_controller_ = msg;
}

void RunRecord::OnContactPlan(int64_t receive_us, const rbcp_msgs::contact_plan_t& msg) {
  Received(receive_us);
  ContactPlan plan = transport::FromContactPlanMsg(msg);
  plans_ += 1;
  if (msg.reaches_goal) goal_plans_ += 1;
  plans_by_seq_[msg.plan_seq] = std::move(plan);
  if (!wait_ || wait_->answered) return;
  const auto it = wait_->first_receipt.find(msg.start_utime);
  if (it == wait_->first_receipt.end()) return;
  wait_->answered = true;
  if (plans_ == 1) return;  // the first plan waits for the world and the path: not a replan
  latencies_ms_.push_back(1e-3 * static_cast<double>(receive_us - it->second));
  latency_times_s_.push_back(1e-6 * static_cast<double>(msg.start_utime));
}

ContactPlan RunRecord::ExecutedPlan(std::vector<std::string>* missing) const {
  ContactPlan executed;
  executed.reaches_goal = false;
  for (std::size_t k = 0; k < segments_.size(); ++k) {
    const Segment& s = segments_[k];
    const auto it = plans_by_seq_.find(s.plan_seq);
    if (it == plans_by_seq_.end()) {
      const std::string what = "plan " + std::to_string(s.plan_seq) + " was walked but never received";
      if (!missing) throw InputError("run record: " + what);
      missing->push_back(what);
      executed.reaches_goal = false;
      continue;
    }
    const ContactPlan& plan = it->second;
    const int end_steps = k + 1 < segments_.size() ? segments_[k + 1].steps_at_start : latest_controller_->steps_done;
    const int walked = std::clamp(end_steps - s.steps_at_start, 0, static_cast<int>(plan.states.size()) - 1);
    if (executed.states.empty()) executed.states.push_back(plan.states.front());
    for (int i = 1; i <= walked; ++i) executed.states.push_back(plan.states[static_cast<std::size_t>(i)]);
    executed.reaches_goal = plan.reaches_goal && walked == static_cast<int>(plan.states.size()) - 1;
  }
  executed.ClearTiming();  // each piece was timed from its own start
  return executed;
}

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double k = std::clamp(p, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(k));
  const std::size_t j = std::min(values.size() - 1, i + 1);
  return values[i] + (k - static_cast<double>(i)) * (values[j] - values[i]);
}

}  // namespace rbcp::nodes
