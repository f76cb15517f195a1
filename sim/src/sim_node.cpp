#include "rbcp/sim/sim_node.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"
#include "rbcp_msgs/point_cloud_t.hpp"

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
    if (!f.should_have_caught.empty()) os << " [should have been caught: " << f.should_have_caught << "]";
  } else {
    os << "undecided after " << FixedNumber(o.sim_time_s, 1) << " s";
  }
  os << "; max torque " << FixedNumber(100.0 * o.max_torque_ratio, 0) << "% of the limit, " << o.collisions
     << " body-terrain collisions";
  return os.str();
}

namespace {

/// `cloud` with the utime and base pose of the ROBOT_STATE of its tick (`carried`), as it carries them.
rbcp_msgs::point_cloud_t ToPointCloudMsg(const PointCloud& cloud, const rbcp_msgs::robot_state_t& carried) {
  rbcp_msgs::point_cloud_t msg{};
  msg.utime = carried.utime;
  msg.sensor = cloud.sensor;
  msg.seq = cloud.seq;
  for (int k = 0; k < 3; ++k) msg.base_position[k] = carried.base_position[k];
  for (int k = 0; k < 4; ++k) msg.base_orientation[k] = carried.base_orientation[k];
  const Eigen::Quaterniond q(cloud.mount.linear());
  for (int k = 0; k < 3; ++k) msg.mount_position[k] = cloud.mount.translation()[k];
  msg.mount_orientation[0] = q.w();
  msg.mount_orientation[1] = q.x();
  msg.mount_orientation[2] = q.y();
  msg.mount_orientation[3] = q.z();
  msg.min_range = static_cast<float>(cloud.min_range_m);
  msg.max_range = static_cast<float>(cloud.max_range_m);
  msg.range_noise_std = static_cast<float>(cloud.range_noise_m);
  msg.num_rays = cloud.num_rays;
  msg.num_points = static_cast<int32_t>(cloud.points.size());
  msg.points.reserve(cloud.points.size());
  for (const Eigen::Vector3f& p : cloud.points) msg.points.push_back({p.x(), p.y(), p.z()});
  return msg;
}

}  // namespace

const EnumNames<TerrainSource>& TerrainSourceNames() {
  static const EnumNames<TerrainSource> names = {{TerrainSource::kGroundTruth, "ground_truth"},
                                                 {TerrainSource::kPerceived, "perceived"}};
  return names;
}

namespace {

/// The sensing the node runs: the configured sensors when the planners plan on their map, none
/// otherwise.
SensingConfig SensingFor(const SimConfig& config, const SimNodeOptions& options) {
  SensingConfig sensing = config.sensing;
  if (options.terrain == TerrainSource::kGroundTruth) sensing.enabled = false;
  return sensing;
}

}  // namespace

SimNode::SimNode(lcm::LCM& lcm, PlanExecution& execution, const Scenario& scenario, const SimConfig& config,
                 SimNodeOptions options)
    : lcm_(lcm),
      execution_(execution),
      scenario_(scenario),
      config_(config),
      status_(lcm, kProcessName, channels::kStatus),
      publisher_(lcm),
      sensors_(SensingFor(config, options), config.control_rate_hz),
      options_(std::move(options)),
      plans_in_(lcm, channels::kContactPlan),
      planner_failures_(lcm, channels::kStatus, [this](const rbcp_msgs::process_status_t& s) {
        return s.process == options_.contact_planner && s.state == rbcp_msgs::process_status_t::FAILED;
      }),
      mapper_status_(lcm, channels::kStatus,
                     [this](const rbcp_msgs::process_status_t& s) { return s.process == options_.mapper; }),
      requests_(lcm, channels::kPlanRequest) {
  if (!(options_.await_timeout_s > 0.0) || !(options_.retry_hold_s >= 0.0) || options_.max_failed_waits < 1) {
    throw InputError("simulator: await_timeout_s expected > 0, retry_hold_s >= 0 and max_failed_waits >= 1");
  }
  if (options_.terrain == TerrainSource::kPerceived && sensors_.Empty()) {
    throw InputError("simulator: a perceived terrain needs a depth sensor (sim.yaml sensing: enabled, and a camera enabled)");
  }
  execution_.SetAwaitPlans(options_.replan);
  execution_.StandAt(scenario_.start);
  // On a perceived terrain the robot looks around, standing, before it waits for its first plan.
  if (options_.terrain == TerrainSource::kPerceived) hold_until_s_ = config_.sensing.look_before_walking_s;
  element_names_.assign(execution_.CurrentWorld().terrain.size(), "");
  terrain_id_ = transport::TerrainId(execution_.CurrentWorld().terrain_mesh);
}

int64_t SimNode::Utime() const { return static_cast<int64_t>(std::llround(execution_.Time() * 1e6)); }

void SimNode::PublishTerrain() {
  last_terrain_wall_ = std::chrono::steady_clock::now();
  const auto msg = transport::ToTerrainMsg(execution_.CurrentWorld().terrain_mesh, Utime(), scenario_.name);
  const bool perceived = options_.terrain == TerrainSource::kPerceived;
  const std::string problem = publisher_.Publish(perceived ? channels::kTerrainTruth : channels::kTerrain, msg);
  if (!problem.empty()) status_.Failed(Utime(), Utime(), 0.0, problem);
}

void SimNode::TakePlan(const rbcp_msgs::contact_plan_t& msg) {
  // The contact planner sends its plan again for a process that missed it: the plan being
  // walked is not started over (replanning: a plan from a stance left is stale, below).
  if (!options_.replan && plans_ > 0 && msg.plan_seq == plan_seq_ && msg.request_id == plan_request_id_ && msg.utime == plan_utime_) return;
  const char* stale_why = nullptr;
  if (const auto* goal = requests_taken_.Latest(); goal && msg.request_id != goal->request_id) {
    stale_why = "it answers another goal";
  }
  // On a perceived terrain the plan was made on a map, which the true terrain cannot judge.
  if (options_.terrain == TerrainSource::kGroundTruth && msg.terrain_id != terrain_id_) {
    stale_why = "it was planned on another terrain";
  }
  if (stale_why) {
    stale_plans_ += 1;
    if (status_.verbose()) {
      std::fprintf(stderr, "[%s] dropped stale CONTACT_PLAN %lld: %s\n", kProcessName,
                   static_cast<long long>(msg.plan_seq), stale_why);
    }
    return;
  }
  if (options_.replan && (!awaiting_since_ || msg.start_utime < *awaiting_since_)) {
    // Planned from a stance the robot has left (or for a wait already given up): stale.
    stale_plans_ += 1;
    if (status_.verbose()) {
      std::fprintf(stderr, "[%s] dropped stale CONTACT_PLAN %lld: starts from utime %lld, %s\n", kProcessName,
                   static_cast<long long>(msg.plan_seq), static_cast<long long>(msg.start_utime),
                   awaiting_since_ ? ("the robot waits since " + std::to_string(*awaiting_since_)).c_str()
                                   : "the robot is not waiting for a plan");
    }
    return;
  }
  try {
    const ContactPlan plan = transport::FromContactPlanMsg(msg);
    execution_.GivePlan(plan);
    plans_ += 1;
    plan_seq_ = msg.plan_seq;
    plan_request_id_ = msg.request_id;
    walked_plan_terrain_id_ = msg.terrain_id;
    failed_waits_ = 0;
    awaiting_since_.reset();
    answered_utime_ = Utime();
    reported_ = false;
    plan_utime_ = msg.utime;
    last_step_reported_ = -1;
    status_.Busy(Utime(), msg.utime);
  } catch (const InputError& e) {
    status_.Failed(Utime(), msg.utime, 0.0, std::string("rejected CONTACT_PLAN: ") + e.what());
  }
}

void SimNode::UpdateWait() {
  const bool failed = [&] {
    const auto f = planner_failures_.Take();
    return f && awaiting_since_ && f->input_utime >= *awaiting_since_;
  }();
  if (!options_.replan || execution_.Decided() || !execution_.Awaiting()) {
    awaiting_since_.reset();
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  if (!awaiting_since_) {
    // A new wait once the controller has seen the last answer (the world moved on since) and
    // any hold is over.
    if (execution_.Time() + 1e-9 < hold_until_s_ || Utime() <= answered_utime_) return;
    awaiting_since_ = Utime();
    await_wall_start_ = now;
    return;
  }
  const bool timed_out = std::chrono::duration<double>(now - await_wall_start_).count() > options_.await_timeout_s;
  if (!failed && !timed_out) return;
  // The rest of the current plan is walked only if it was planned on the world as it is.
  const bool go_on = execution_.CanContinue() &&
                     (options_.terrain == TerrainSource::kPerceived || walked_plan_terrain_id_ == terrain_id_);
  if (status_.verbose()) {
    std::fprintf(stderr, "[%s] no new plan for the wait since utime %lld (%s): %s\n", kProcessName,
                 static_cast<long long>(*awaiting_since_), failed ? "the contact planner failed" : "timed out",
                 go_on ? "going on with the current plan" : "holding the stance");
  }
  if (go_on) {
    execution_.ContinuePlan();
  } else if (++failed_waits_ >= options_.max_failed_waits) {
    execution_.Abort("no_plan", "no plan from this stance after " + std::to_string(failed_waits_) +
                                    " waits in a row" + (failed ? " (the contact planner failed)" : " (no answer)"));
  } else {
    hold_until_s_ = execution_.Time() + options_.retry_hold_s;
  }
  awaiting_since_.reset();
  answered_utime_ = Utime();
}

void SimNode::PublishState() {
  const RobotState state = execution_.State();
  const auto state_msg = transport::ToRobotStateMsg(state);
  // The tick's clouds first: a mapper that hears of a wait has every cloud up to it. Then the
  // controller's status: a process that hears of a wait then hears the state it waits in.
  PublishClouds(state, state_msg);
  const ControllerStatus& status = execution_.Controller().Status();
  ControllerProgress progress;
  progress.plan_seq = plan_seq_;
  progress.steps_done = status.steps_done;
  progress.awaiting_since = awaiting_since_;
  progress.phase = ToString(status.phase);
  progress.step = status.step;
  progress.swing_leg = status.swing_leg ? Index(*status.swing_leg) : -1;
  progress.base_error_m = status.base_error_m;
  progress.step_max_base_error_m = status.step_max_base_error_m;
  progress.support_margin_m = status.support_margin_m;
  progress.steps_committed = execution_.Controller().CommittedSteps();
  progress.lag_s = status.lag_s;
  const auto progress_msg = transport::ToControllerStatusMsg(state_msg.utime, progress);
  lcm_.publish(channels::kControllerStatus, &progress_msg);
  lcm_.publish(channels::kRobotState, &state_msg);
}

void SimNode::PublishClouds(const RobotState& state, const rbcp_msgs::robot_state_t& state_msg) {
  if (sensors_.Empty()) return;
  const std::vector<PointCloud> clouds = sensors_.CaptureIfDue(execution_.World(), state);
  for (const PointCloud& cloud : clouds) {
    const std::string problem = publisher_.Publish(channels::kPointCloud, ToPointCloudMsg(cloud, state_msg));
    if (problem.empty()) {
      point_clouds_ += 1;
    } else {
      status_.Failed(state_msg.utime, state_msg.utime, 0.0, problem);
    }
  }
}

void SimNode::ApplyEvents() {
  if (push_until_s_ >= 0.0 && execution_.Time() + 1e-9 >= push_until_s_) {
    execution_.SetBaseForce(Eigen::Vector3d::Zero());
    push_until_s_ = -1.0;
    if (status_.verbose()) std::fprintf(stderr, "[%s] the push ends at %.2f s\n", kProcessName, execution_.Time());
  }
  // The events due now change the terrain together: one new world, one TERRAIN.
  TerrainEdit edit{execution_.CurrentWorld().terrain, element_names_, false};
  while (next_event_ < options_.events.size() && options_.events[next_event_].t <= execution_.Time() + 1e-9) {
    const WorldEvent& e = options_.events[next_event_++];
    try {
      Apply(e, edit);
      if (status_.verbose()) {
        std::fprintf(stderr, "[%s] event at %.2f s: %s\n", kProcessName, execution_.Time(), e.Describe().c_str());
      }
    } catch (const InputError& error) {
      status_.Failed(Utime(), Utime(), 0.0, "event " + e.Describe() + ": " + error.what());
    }
  }
  if (edit.changed) {
    try {
      execution_.SetTerrain(edit.terrain);
      element_names_ = std::move(edit.names);
      // The terrain changed: everyone hears of it at once; plans made on the old one are stale.
      terrain_id_ = transport::TerrainId(execution_.CurrentWorld().terrain_mesh);
      PublishTerrain();
    } catch (const InputError& error) {
      status_.Failed(Utime(), Utime(), 0.0, std::string("the events' terrain: ") + error.what());
    }
  }
  if (own_request_ && std::chrono::steady_clock::now() - own_request_wall_ >= std::chrono::seconds(1)) {
    // The goal again, for a root planner that restarted since.
    own_request_wall_ = std::chrono::steady_clock::now();
    lcm_.publish(channels::kPlanRequest, &*own_request_);
  }
}

void SimNode::Apply(const WorldEvent& e, TerrainEdit& edit) {
  switch (e.kind) {
    case WorldEvent::Kind::kAddBox:
      edit.terrain.push_back(e.box);
      edit.names.push_back(e.name);
      edit.changed = true;
      return;
    case WorldEvent::Kind::kRemoveBox: {
      const auto it = std::find(edit.names.begin(), edit.names.end(), e.name);
      if (it == edit.names.end()) throw InputError("no box named '" + e.name + "' in the world");
      edit.terrain.erase(edit.terrain.begin() + (it - edit.names.begin()));
      edit.names.erase(it);
      edit.changed = true;
      return;
    }
    case WorldEvent::Kind::kPush:
      execution_.SetBaseForce(e.force_W);
      push_until_s_ = execution_.Time() + e.duration_s;
      return;
    case WorldEvent::Kind::kGoal: {
      rbcp_msgs::plan_request_t r{};
      const rbcp_msgs::plan_request_t* latest = requests_taken_.Latest();
      if (latest) r = *latest;
      r.utime = Utime();
      r.request_id = (latest ? latest->request_id : 0) + 1;
      r.use_start = false;
      r.goal_position[0] = e.goal.position.x();
      r.goal_position[1] = e.goal.position.y();
      r.goal_position[2] = 0.0;
      r.goal_yaw = e.goal.yaw;
      if (!latest) r.seed = 1;
      requests_taken_.Take(r);
      own_request_ = r;
      own_request_wall_ = std::chrono::steady_clock::now();
      lcm_.publish(channels::kPlanRequest, &r);
      return;
    }
  }
}

void SimNode::Tick() {
  if (auto error = plans_in_.TakeDecodeError()) status_.Failed(Utime(), 0, 0.0, *error);
  if (auto request = requests_.Take()) {
    // Ids identify requests, they are not ordered: the latest new request is the goal, and a late
    // repeat of one given up since (its operator repeats it every second) is not.
    if (!requests_taken_.Superseded(*request)) requests_taken_.Take(*request);
  }
  if (auto msg = plans_in_.Take()) TakePlan(*msg);
  if (options_.terrain == TerrainSource::kPerceived && !mapper_heard_) {
    // Nothing starts before the mapper listens: the robot's first look would be lost on it.
    mapper_heard_ = mapper_status_.Latest().has_value();
    if (!mapper_heard_) return;
    if (status_.verbose()) std::fprintf(stderr, "[%s] %s is up: the world starts\n", kProcessName, options_.mapper.c_str());
  }
  UpdateWait();
  if (Paused()) {
    // The world stands still while the robot waits; the state goes out every few milliseconds.
    const auto now = std::chrono::steady_clock::now();
    if (now - last_state_wall_ >= std::chrono::milliseconds(5)) {
      last_state_wall_ = now;
      PublishState();  // with a capture due at this tick, once
    }
    // The terrain, due every terrain_period_s of simulated time, goes out on the wall clock meanwhile.
    if (now - last_terrain_wall_ >= std::chrono::duration<double>(config_.terrain_period_s)) PublishTerrain();
    return;
  }
  if (execution_.Time() + 1e-9 >= next_terrain_s_) {
    PublishTerrain();
    next_terrain_s_ += config_.terrain_period_s;
  }
  ApplyEvents();
  execution_.Tick();
  UpdateWait();
  PublishState();

  if ((plans_ > 0 || options_.replan) && execution_.Decided() && !reported_) {
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
