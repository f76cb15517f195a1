#include "rbcp/sim/sim_node.h"

#include <cmath>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"

namespace rbcp::sim {
std::string OutcomeSummary(const ExecutionOutcome& o) {
  std::ostringstream os;
  if (o.ok()) {
    os << "goal reached in " << FixedNumber(o.sim_time_s, 1) << " s of simulated time, " << o.steps_executed << " steps";
  } else if (o.failure) {
    const ExecutionFailure& f = *o.failure;
    os << f.what << " at " << FixedNumber(f.t, 2) << " s, step " << f.step << "/" << o.steps_total;
    if (!f.leg.empty()) os << " (" << f.leg << ")";
    if (!f.phase.empty()) os << " during " << f.phase;
    os << ": " << f.detail;
  } else {
    os << "undecided after " << FixedNumber(o.sim_time_s, 1) << " s";
  }
  os << "; max torque " << FixedNumber(100.0 * o.max_torque_ratio, 0) << "% of the limit, " << o.collisions
     << " body-terrain collisions";
  return os.str();
}

SimNode::SimNode(lcm::LCM& lcm, PlanExecution& execution, const Scenario& scenario, const SimConfig& config)
    : lcm_(lcm),
      execution_(execution),
      scenario_(scenario),
      config_(config),
      status_(lcm, kProcessName, channels::kStatus),
      plans_in_(lcm, channels::kContactPlan) {
  execution_.StandAt(scenario_.start);
}

int64_t SimNode::Utime() const { return static_cast<int64_t>(std::llround(execution_.Time() * 1e6)); }

void SimNode::PublishTerrain() {
  const auto msg = transport::ToTerrainMsg(scenario_.terrain_mesh, Utime(), scenario_.name);
  lcm_.publish(channels::kTerrain, &msg);
}

void SimNode::Tick() {
  if (auto error = plans_in_.TakeDecodeError()) status_.Failed(Utime(), 0, 0.0, *error);
  if (auto msg = plans_in_.Take()) {
    try {
      const ContactPlan plan = transport::FromContactPlanMsg(*msg);
      execution_.GivePlan(plan);
      plans_ += 1;
      reported_ = false;
      plan_utime_ = msg->utime;
      last_step_reported_ = -1;
      status_.Busy(Utime(), msg->utime);
    } catch (const InputError& e) {
      status_.Failed(Utime(), msg->utime, 0.0, std::string("rejected CONTACT_PLAN: ") + e.what());
    }
  }
  if (execution_.Time() + 1e-9 >= next_terrain_s_) {
    PublishTerrain();
    next_terrain_s_ += config_.terrain_period_s;
  }
  execution_.Tick();
  const auto state_msg = transport::ToRobotStateMsg(execution_.State());
  lcm_.publish(channels::kRobotState, &state_msg);

  if (plans_ > 0 && execution_.Decided() && !reported_) {
    reported_ = true;
    const ExecutionOutcome& o = execution_.Outcome();
    if (o.ok()) {
      status_.Ok(Utime(), plan_utime_, 0.0, OutcomeSummary(o));
    } else {
      status_.Failed(Utime(), plan_utime_, 0.0, OutcomeSummary(o));
    }
  }
}

void SimNode::Heartbeat() { status_.Heartbeat(Utime()); }

}  // namespace rbcp::sim
