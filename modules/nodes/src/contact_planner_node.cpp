#include "rbcp/nodes/contact_planner_node.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <limits>
#include <sstream>
#include <utility>

#include "rbcp/core/angle.h"
#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/transport/convert.h"
#include "rbcp_msgs/contact_plan_t.hpp"

namespace rbcp::nodes {
namespace {

/// The first samples of `samples` up to the first one at which the map shows no terrain under
/// one of the robot's reference feet (the first sample always).
std::vector<RootPathSample> AsFarAsTheMapShows(const std::vector<RootPathSample>& samples, const TriangleMesh& terrain,
                                               const RobotModel& robot) {
  const TerrainHeightMap heights(terrain);
  std::size_t n = 1;
  for (; n < samples.size(); ++n) {
    const Eigen::Isometry3d base = Eigen::Translation3d(samples[n].p) * Eigen::AngleAxisd(samples[n].yaw, Eigen::Vector3d::UnitZ());
    const bool seen = std::all_of(kAllLegs.begin(), kAllLegs.end(), [&](Leg leg) {
      return heights.At((base * robot.ReferenceFootPosition(leg)).head<2>()).has_value();
    });
    if (!seen) break;
  }
  return std::vector<RootPathSample>(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(std::min(n, samples.size())));
}

/// The feet where forward kinematics of the measured joints puts them, in the world frame.
std::array<Eigen::Vector3d, kNumLegs> MeasuredFeetW(const RobotModel& robot, const RobotState& measured) {
  const Eigen::Isometry3d base_W = Eigen::Translation3d(measured.base_position_W) * measured.base_orientation_W;
  std::array<Eigen::Vector3d, kNumLegs> feet_W = robot.FootPositions(measured.q);
  for (Eigen::Vector3d& p : feet_W) p = base_W * p;
  return feet_W;
}

/// The largest difference of roll, pitch and yaw between two base poses [rad].
double OrientationDifference(const WholeBodyState& a, const WholeBodyState& b) {
  Eigen::Vector3d d = a.base_rpy - b.base_rpy;
  d.z() = WrapAngle(d.z());
  return d.cwiseAbs().maxCoeff();
}

/// How far the trunk may be beyond the terrain's horizontal bounds, feet still on the terrain [m].
constexpr double kTerrainMargin_m = 0.5;

std::string Summary(const ContactPlanResult& r, int horizon_steps) {
  std::ostringstream os;
  os << r.steps << " steps, " << r.plan.states.size() << " states";
  if (horizon_steps > 0) os << " (horizon " << horizon_steps << ")";
  os << (r.reached_goal ? ", reaches the goal" : ", goal not reached yet");
  os.precision(3);
  os << ", planned in " << r.planning_time_s << " s";
  return os.str();
}

}  // namespace

bool KeepEarlierSearch(const ContactPlan& continuation, const ContactPlanResult& fresh, int k, int margin,
                       const std::function<std::size_t(const WholeBodyState&)>& progress) {
  const int steps = static_cast<int>(continuation.states.size()) - 1;
  if (steps < 1) return false;
  if (!fresh.ok) return true;
  if (!continuation.reaches_goal && steps < k + margin) return false;
  const auto after_k = [&](const ContactPlan& plan) {
    return progress(plan.states[std::min(plan.states.size() - 1, static_cast<std::size_t>(std::max(k, 0)))]);
  };
  return after_k(continuation) > after_k(fresh.plan);
}

ContactPlannerNode::ContactPlannerNode(lcm::LCM& lcm, const RobotModel& robot, const LimbDatabase& database,
                                       const EquilibriumConfig& equilibrium, const ContactPlannerConfig& config,
                                       const StanceConfig& stance, ContactPlannerNodeOptions options)
    : lcm_(lcm),
      robot_(robot),
      options_(std::move(options)),
      planner_(robot, database, equilibrium, config, stance),
      ahead_planner_(robot, database, equilibrium, config, stance),
      root_path_(lcm, options_.root_path_channel),
      robot_state_(lcm, options_.robot_state_channel),
      controller_(lcm, options_.controller_status_channel),
      world_(lcm, options_.terrain_channel, options_.affordances_channel),
      status_(lcm, kProcessName, options_.status_channel) {
  if (options_.horizon_steps < 0) {
    throw InputError("contact planner node: horizon_steps expected >= 0, got " + std::to_string(options_.horizon_steps));
  }
  if (!(options_.max_foot_offset_m > 0.0)) {
    throw InputError("contact planner node: max_foot_offset_m expected > 0, got " +
                     std::to_string(options_.max_foot_offset_m));
  }
  if (options_.lookahead_steps < 0 || options_.partial_lookahead_steps < 0) {
    throw InputError("contact planner node: lookahead_steps and partial_lookahead_steps expected >= 0, got " +
                     std::to_string(options_.lookahead_steps) + " and " +
                     std::to_string(options_.partial_lookahead_steps));
  }
  if (!(options_.foothold_match_m >= 0.0)) {
    throw InputError("contact planner node: foothold_match_m expected >= 0, got " +
                     std::to_string(options_.foothold_match_m));
  }
  if (options_.reuse_margin_steps < 0) {
    throw InputError("contact planner node: reuse_margin_steps expected >= 0, got " +
                     std::to_string(options_.reuse_margin_steps));
  }
  if (!(options_.base_match_m >= 0.0) || !(options_.base_match_rad >= 0.0)) {
    throw InputError("contact planner node: base_match_m and base_match_rad expected >= 0");
  }
  if (!(options_.resend_period_s >= 0.0)) {
    throw InputError("contact planner node: resend_period_s expected >= 0");
  }
  if (!(options_.max_path_offset_m > 0.0)) {
    throw InputError("contact planner node: max_path_offset_m expected > 0, got " +
                     std::to_string(options_.max_path_offset_m));
  }
}

ContactPlannerNode::~ContactPlannerNode() { WaitForSearchWorker(); }

int64_t ContactPlannerNode::Now() const { return clock_.Now(); }

void ContactPlannerNode::set_verbose(bool verbose) {
  verbose_ = verbose;
  status_.set_verbose(verbose);
}

std::optional<RejectedInput> ContactPlannerNode::TakeInputs() {
  if (auto e = root_path_.TakeDecodeError()) return RejectedInput::Undecodable(std::move(*e));
  if (auto e = robot_state_.TakeDecodeError()) return RejectedInput::Undecodable(std::move(*e));
  if (auto e = controller_.TakeDecodeError()) return RejectedInput::Undecodable(std::move(*e));
  if (const auto& state = robot_state_.Latest()) {
    if (auto bad = clock_.World(state->utime, options_.robot_state_channel)) {
      return RejectedInput::Time(std::move(*bad));
    }
  }
  if (auto e = world_.Take(&clock_)) return e;
  if (world_.TakeChanged()) {
    world_set_ = false;
    // On a growing map the plan made ahead is made on the map it started on, and checked on the
    // map of the wait (Replan).
    if (options_.partial_map) {
      FinishPlanAhead();
    } else {
      DropPlanAhead();
    }
    if (world_.Ready()) {
      const TriangleMesh& mesh = *world_.terrain();
      terrain_min_xy_ = terrain_max_xy_ = mesh.vertices.front().head<2>();
      for (const Eigen::Vector3d& v : mesh.vertices) {
        terrain_min_xy_ = terrain_min_xy_.cwiseMin(v.head<2>());
        terrain_max_xy_ = terrain_max_xy_.cwiseMax(v.head<2>());
      }
      if (world_.surfaces()->empty()) return RejectedInput::Content("affordances: the terrain has no contact surface");
      try {
        planner_.SetTerrain(mesh, *world_.surfaces());
        WaitForSearchWorker();  // its planner's world changes too
        ahead_planner_.SetTerrain(mesh, *world_.surfaces());
        world_set_ = true;
      } catch (const std::exception& e) {
        return RejectedInput::Content(std::string("terrain: ") + e.what());
      }
    }
  }
  if (auto msg = root_path_.Take()) {
    if (auto bad = clock_.Input(msg->utime, options_.root_path_channel)) return RejectedInput::Time(std::move(*bad));
    pending_ = *msg;
  }
  return std::nullopt;
}

void ContactPlannerNode::LogWaiting() {
  std::string waiting;
  auto add = [&](const char* what) { waiting += (waiting.empty() ? "" : ", ") + std::string(what); };
  if (!world_.terrain()) add(options_.terrain_channel.c_str());
  if (!world_.surfaces()) add(options_.affordances_channel.c_str());
  if (!pending_ && !last_result_) add(options_.root_path_channel.c_str());
  if (pending_ && world_.terrain() && pending_->terrain_id != world_.terrain_id()) {
    add("the terrain its root path was planned on");
  }
  if (waiting == logged_waiting_) return;
  logged_waiting_ = waiting;
  if (verbose_ && !waiting.empty()) std::fprintf(stderr, "[%s] waiting for %s\n", kProcessName, waiting.c_str());
}

bool ContactPlannerNode::Step() {
  if (auto rejected = TakeInputs()) {
    status_.Failed(Now(), Now(), 0.0, rejected->Describe());
    return true;
  }
  LogWaiting();
  if (options_.horizon_steps > 0) {
    bool worked = false;
    if (PendingPathFitsTheWorld()) {
      const rbcp_msgs::root_path_t msg = std::move(*pending_);
      pending_.reset();
      TakePath(msg);
      worked = true;
    }
    // A wait of the controller, and the measured state it waits in (the world stands still).
    const auto& state = robot_state_.Latest();
    const auto& controller = controller_.Latest();
    if (!state || !controller || !controller->awaiting_plan || state->utime < controller->awaiting_since ||
        !world_set_ || path_.empty()) {
      return worked;
    }
    if (options_.partial_map && world_.terrain_utime() < controller->awaiting_since) {
      return worked;  // the map of this wait is on its way
    }
    if (path_terrain_id_ != world_.terrain_id()) {
      if (verbose_ && !logged_stale_) std::fprintf(stderr, "[%s] the terrain changed: waiting for a root path on it\n", kProcessName);
      logged_stale_ = true;
      return worked;
    }
    if (answered_since_ == controller->awaiting_since) return ResendIfStillAwaited(*controller) || worked;
    answered_since_ = controller->awaiting_since;
    Replan(*state, *controller);
    return true;
  }
  if (!PendingPathFitsTheWorld()) return false;
  const rbcp_msgs::root_path_t msg = std::move(*pending_);
  pending_.reset();
  Plan(msg);
  return true;
}

bool ContactPlannerNode::PendingPathFitsTheWorld() const {
  // A path planned on another terrain waits: the terrain it was planned on may still be on its
  // way (a large terrain comes in parts), or the root planner plans again on this one.
  return pending_ && world_set_ && pending_->terrain_id == world_.terrain_id();
}

bool ContactPlannerNode::SamePath(const rbcp_msgs::root_path_t& msg, const std::vector<RootPathSample>& samples) const {
  const auto same_sample = [](const RootPathSample& a, const RootPathSample& b) {
    return a.t == b.t && a.p == b.p && a.v == b.v && a.yaw == b.yaw;
  };
  return msg.request_id == path_request_id_ && samples.size() == path_.size() &&
         std::equal(samples.begin(), samples.end(), path_.begin(), same_sample);
}

bool ContactPlannerNode::IsRepeat(const rbcp_msgs::root_path_t& msg, const std::vector<RootPathSample>& samples) const {
  return msg.terrain_id == path_terrain_id_ && SamePath(msg, samples);
}

void ContactPlannerNode::TakePath(const rbcp_msgs::root_path_t& msg) {
  std::vector<RootPathSample> samples;
  if (auto problem = ToSamples(msg, &samples)) {
    status_.Failed(Now(), msg.utime, 0.0, problem->Describe());
    return;
  }
  if (IsRepeat(msg, samples)) return;  // the root planner repeats its path for late processes
  // Request ids identify goals, they are not ordered: the latest goal's path is followed. An
  // older path of the same goal, come late (the network reordered it), is superseded.
  if (!path_.empty() && msg.request_id == path_request_id_ && msg.utime < path_utime_) return;
  logged_stale_ = false;
  if (SamePath(msg, samples)) {
    // The same path on a new map (a mapped terrain that grew): the walk along it goes on.
    path_terrain_id_ = msg.terrain_id;
    path_reaches_goal_ = msg.reaches_goal;
    path_utime_ = msg.utime;
    return;
  }
  path_ = std::move(samples);
  path_request_id_ = msg.request_id;
  path_terrain_id_ = msg.terrain_id;
  path_reaches_goal_ = msg.reaches_goal;
  path_utime_ = msg.utime;
  path_progress_ = 0;
  answered_since_.reset();  // a wait already answered on the old path gets a plan on the new one
  // On a growing map new paths come often; the robot still stands on the footholds of the plan it
  // walks, and its feet are snapped to them (SnapToLastPlan) so that the walk goes on from there.
  if (!options_.partial_map) last_plan_.reset();
  answer_.reset();
  DropPlanAhead();
  if (verbose_) {
    std::fprintf(stderr, "[%s] following the root path of request %lld: %zu points, %.2f s\n", kProcessName,
                 static_cast<long long>(msg.request_id), path_.size(), path_.back().t - path_.front().t);
  }
}

std::size_t ContactPlannerNode::PathProgress(const Eigen::Vector3d& base_W, double yaw, double* offset_xy) const {
  // The sample nearest to the base (position, and heading at 0.3 m/rad), not behind the last one.
  std::size_t nearest = path_progress_;
  double best = std::numeric_limits<double>::infinity();
  *offset_xy = best;
  for (std::size_t i = path_progress_; i < path_.size(); ++i) {
    const double xy = (path_[i].p.head<2>() - base_W.head<2>()).norm();
    const double d = xy + 0.3 * std::abs(WrapAngle(path_[i].yaw - yaw));
    if (d < best) {
      best = d;
      *offset_xy = xy;
      nearest = i;
    }
  }
  return nearest;
}

std::string StanceDeviation::Describe() const {
  std::ostringstream os;
  os.precision(3);
  switch (kind) {
    case Kind::kFoothold: os << LegName(leg) << " stands " << amount << " m from its planned foothold"; break;
    case Kind::kBasePosition: os << "the base is " << amount << " m off the controller's reference"; break;
    case Kind::kBaseOrientation: os << "the base is " << amount << " rad from its planned orientation"; break;
  }
  return os.str();
}

std::string PlanAheadMissed::Describe() const {
  switch (kind) {
    case Kind::kNone: return "no plan made ahead";
    case Kind::kOtherPlan: return "the robot walks another plan than the one planned ahead";
    case Kind::kStanceDeviates: return deviation ? deviation->Describe() : "the robot stands elsewhere";
    case Kind::kFailed: return "the plan made ahead failed";
    case Kind::kMapChanged: return "the plan made ahead does not hold on the map of this wait";
  }
  return "the plan made ahead is not taken";
}

std::optional<StanceDeviation> ContactPlannerNode::Deviation(const WholeBodyState& measured,
                                                             const WholeBodyState& expected,
                                                             double base_error_m) const {
  for (std::size_t i = 0; i < measured.feet.size(); ++i) {
    const double d = (measured.feet[i].position - expected.feet[i].position).norm();
    if (d > 0.0) return StanceDeviation{StanceDeviation::Kind::kFoothold, kAllLegs[i], d};
  }
  if (base_error_m > options_.base_match_m) {
    return StanceDeviation{StanceDeviation::Kind::kBasePosition, Leg::kLF, base_error_m};
  }
  const double drpy = OrientationDifference(measured, expected);
  if (drpy > options_.base_match_rad) return StanceDeviation{StanceDeviation::Kind::kBaseOrientation, Leg::kLF, drpy};
  return std::nullopt;
}

const WholeBodyState* ContactPlannerNode::ReachedPlanState(const rbcp_msgs::controller_status_t& controller) const {
  if (!last_plan_ || controller.plan_seq != plan_seq_) return nullptr;
  const long walked = static_cast<long>(controller.steps_done) - static_cast<long>(plan_start_steps_);
  if (walked < 1 || walked >= static_cast<long>(last_plan_->states.size())) return nullptr;
  return &last_plan_->states[static_cast<std::size_t>(walked)];
}

int ContactPlannerNode::SnapToLastPlan(const rbcp_msgs::controller_status_t& controller,
                                       WholeBodyState* stance) const {
  if (!last_plan_) return 0;
  // A foot still on a foothold of the previous plan stands exactly there: the one of the state
  // the robot should have reached, else the nearest.
  const WholeBodyState* reached = ReachedPlanState(controller);
  int on_plan = 0;
  for (std::size_t i = 0; i < stance->feet.size(); ++i) {
    const FootContact* match = nullptr;
    double best_d = options_.foothold_match_m;
    if (reached && (reached->feet[i].position - stance->feet[i].position).norm() <= best_d) {
      match = &reached->feet[i];
    }
    for (const WholeBodyState& s : last_plan_->states) {
      if (match) break;
      const double d = (s.feet[i].position - stance->feet[i].position).norm();
      if (d <= best_d) {
        best_d = d;
        match = &s.feet[i];
      }
    }
    if (match) {
      stance->feet[i] = *match;
      ++on_plan;
    }
  }
  if (!reached) return on_plan;
  // The crawl goes on from the last step the robot walked of that plan.
  stance->moving_leg = reached->moving_leg;
  // On the planned footholds, with the base on the reference the controller tracks, the base
  // stands where the plan put it: the controller walks the plan (in the dynamic walk its CoM
  // sways around the plan's base poses along the trajectory the planner checked).
  if (on_plan == static_cast<int>(stance->feet.size()) && controller.base_error <= options_.base_match_m &&
      OrientationDifference(*stance, *reached) <= options_.base_match_rad) {
    stance->base_position = reached->base_position;
    stance->base_rpy = reached->base_rpy;
  }
  return on_plan;
}

std::optional<PlanAheadMissed> ContactPlannerNode::WhyNotPlannedAhead(
    const std::optional<PlanMadeAhead>& ahead, const WholeBodyState& stance,
    const rbcp_msgs::controller_status_t& controller) const {
  using Kind = PlanAheadMissed::Kind;
  if (!ahead) return PlanAheadMissed{Kind::kNone, std::nullopt};
  if (ahead->after_plan_seq != controller.plan_seq) return PlanAheadMissed{Kind::kOtherPlan, std::nullopt};
  if (std::optional<StanceDeviation> deviation = Deviation(stance, ahead->expected, controller.base_error)) {
    return PlanAheadMissed{Kind::kStanceDeviates, deviation};
  }
  if (!ahead->result.ok) return PlanAheadMissed{Kind::kFailed, std::nullopt};
  return std::nullopt;
}

bool ContactPlannerNode::HoldsOnThisMap(PlanMadeAhead& ahead) {
  ContactPlanResult here = planner_.OnThisTerrain(ahead.result.plan, options_.map_foothold_offset_m);
  if (verbose_) {
    std::fprintf(stderr, "[%s] the map changed since the plan made ahead: it %s (%.3f s)\n", kProcessName,
                 here.ok ? "holds on this one" : ("does not hold: " + here.reason).c_str(), here.planning_time_s);
  }
  if (!here.ok) return false;
  here.reached_goal = ahead.result.reached_goal;
  ahead.result = std::move(here);
  return true;
}

bool ContactPlannerNode::HoldsWithOneFootOff(PlanMadeAhead& ahead, const PlanAheadMissed& missed,
                                             const WholeBodyState& stance,
                                             const rbcp_msgs::controller_status_t& controller) {
  if (missed.kind != PlanAheadMissed::Kind::kStanceDeviates || !ahead.result.ok ||
      missed.deviation->kind != StanceDeviation::Kind::kFoothold) {
    return false;
  }
  // Only that foot is off: the base on the controller's reference, the orientation as planned.
  const std::size_t off = static_cast<std::size_t>(Index(missed.deviation->leg));
  WholeBodyState others = stance;
  others.feet[off] = ahead.expected.feet[off];
  if (Deviation(others, ahead.expected, controller.base_error)) return false;
  WholeBodyState start = ahead.expected;
  start.feet[off] = stance.feet[off];
  ContactPlanResult from_there = planner_.FromStart(ahead.result.plan, start);
  if (verbose_) {
    std::fprintf(stderr, "[%s] %s: the plan made ahead %s (%.3f s)\n", kProcessName,
                 missed.deviation->Describe().c_str(),
                 from_there.ok ? "holds from there" : ("does not hold: " + from_there.reason).c_str(),
                 from_there.planning_time_s);
  }
  if (!from_there.ok) return false;
  ahead.result = std::move(from_there);
  return true;
}

void ContactPlannerNode::Replan(const rbcp_msgs::robot_state_t& msg, const rbcp_msgs::controller_status_t& controller) {
  status_.Busy(Now(), msg.utime);
  const auto fail = [&](const std::string& why) {
    last_result_.reset();
    DropPlanAhead();
    status_.Failed(Now(), msg.utime, 0.0, why);
  };
  RobotState measured;
  try {
    measured = transport::FromRobotStateMsg(msg);
    transport::FromControllerStatusMsg(controller);
  } catch (const InputError& e) {
    return fail(e.what());
  }
  const Eigen::Vector3d rpy = RpyFromRotation(measured.base_orientation_W.toRotationMatrix());
  const std::array<Eigen::Vector3d, kNumLegs> feet_W = MeasuredFeetW(robot_, measured);
  StanceResult measured_stance =
      planner_.MeasuredStance(measured.base_position_W, rpy, feet_W, options_.max_foot_offset_m);
  if (!measured_stance.ok() && measured_stance.status == ContactPlanStatus::kNoStartStance && options_.partial_map) {
    // The map changed under the robot: a foot may stand where the new map has no contact surface
    // (a block's surface shrank by a cell). Feet still on footholds of the previous plan stand
    // there, as they do on a map that still shows them.
    WholeBodyState on_plan;
    on_plan.base_position = measured.base_position_W;
    on_plan.base_rpy = rpy;
    for (std::size_t i = 0; i < feet_W.size(); ++i) on_plan.feet[i].position = feet_W[i];
    if (SnapToLastPlan(controller, &on_plan) == kNumLegs) {
      measured_stance.status = ContactPlanStatus::kOk;
      measured_stance.state = on_plan;
    }
  }
  if (!measured_stance.ok()) return fail("measured stance: " + measured_stance.reason);
  WholeBodyState& stance = *measured_stance.state;
  SnapToLastPlan(controller, &stance);
  double offset_xy = 0.0;
  const std::size_t nearest = PathProgress(measured.base_position_W, rpy.z(), &offset_xy);
  if (offset_xy > options_.max_path_offset_m) {
    std::ostringstream os;
    os.precision(3);
    os << "robot state: the base is " << offset_xy << " m from the root path (at most " << options_.max_path_offset_m
       << " m)";
    return fail(os.str());
  }
  // The plan made ahead, while the robot walked its step, from the stance that step leads to:
  // taken when the robot stands there (the same footholds, the base within base_match_m of the
  // controller's reference and base_match_rad of the planned orientation); otherwise a new plan
  // from the measured stance.
  FinishPlanAhead();
  std::optional<PlanMadeAhead> ahead = std::exchange(plan_made_ahead_, std::nullopt);
  std::optional<PlanAheadMissed> missed = WhyNotPlannedAhead(ahead, stance, controller);
  if (!missed && plan_ahead_terrain_id_ != world_.terrain_id() && !HoldsOnThisMap(*ahead)) {
    missed = PlanAheadMissed{PlanAheadMissed::Kind::kMapChanged, std::nullopt};
  }
  if (missed && HoldsWithOneFootOff(*ahead, *missed, stance, controller)) missed.reset();
  if (!missed) {
    path_progress_ = ahead->progress;
    last_result_ = std::move(ahead->result);
    if (verbose_) {
      std::fprintf(stderr, "[%s] the robot stands where the plan made ahead starts (utime %lld): taking it\n",
                   kProcessName, static_cast<long long>(msg.utime));
    }
  } else {
    path_progress_ = nearest;
    const std::vector<RootPathSample> remaining(path_.begin() + static_cast<std::ptrdiff_t>(nearest), path_.end());
    const int k = options_.horizon_steps;
    if (verbose_) {
      std::fprintf(stderr, "[%s] planning %d steps from the measured stance at utime %lld (%s), base (%.3f, %.3f) %.3f m off the controller's reference, %zu path points left\n",
                   kProcessName, k, static_cast<long long>(msg.utime), missed->Describe().c_str(),
                   measured.base_position_W.x(), measured.base_position_W.y(), controller.base_error, remaining.size());
    }
    try {
      last_result_ = planner_.PlanHorizon(stance, remaining, SearchSteps());
      const ContactPlanStatus status = last_result_->status;
      if (options_.partial_map && path_reaches_goal_ &&
          (status == ContactPlanStatus::kNoFoothold || status == ContactPlanStatus::kGoalUnreachable)) {
        // On a map that grows, the way to the goal may cross cells not seen yet (in the shadow
        // of a block): the steps the map shows, along the path as far as the map shows terrain
        // under the feet, searched as along a path short of the goal.
        const std::vector<RootPathSample> seen = AsFarAsTheMapShows(remaining, *world_.terrain(), robot_);
        ContactPlanResult shorter = planner_.PlanHorizon(stance, seen, PartialSearchSteps());
        shorter.planning_time_s += last_result_->planning_time_s;
        shorter.reached_goal = shorter.reached_goal && seen.size() == remaining.size();
        if (shorter.ok && shorter.steps > 0) {
          last_result_ = std::move(shorter);
        } else {
          last_result_->planning_time_s = shorter.planning_time_s;
          last_result_->reason += " (nor along the path as far as the map shows it: " +
                                  (shorter.ok ? std::string("no step") : shorter.reason) + ")";
        }
      }
    } catch (const std::exception& e) {
      return fail(std::string("internal error: ") + e.what());
    }
  }
  PublishHorizon(msg, controller);
}

void ContactPlannerNode::PublishHorizon(const rbcp_msgs::robot_state_t& msg,
                                        const rbcp_msgs::controller_status_t& controller) {
  ContactPlanResult& r = *last_result_;
  const int k = options_.horizon_steps;
  const double ms = 1000.0 * r.planning_time_s;
  if (!r.ok) {
    status_.Failed(Now(), msg.utime, ms, ToString(r.status) + ": " + r.reason);
    return;
  }
  if (r.plan.states.size() < 2 && !path_reaches_goal_) {
    // At the end of a path short of the goal: nothing to walk until the map shows more.
    last_result_.reset();
    status_.Failed(Now(), msg.utime, ms, "the robot stands at the end of its path, short of the goal (the map does not show the way on yet)");
    return;
  }
  // Publish the first K steps; the look-ahead beyond them only showed they lead on. The whole
  // search is kept: while the robot walks it as planned, its continuation is the next answer.
  searched_ = r.plan;
  searched_.reaches_goal = r.reached_goal;
  const std::size_t keep = static_cast<std::size_t>(k) + 1;
  r.plan.reaches_goal = r.reached_goal && r.plan.states.size() <= keep;
  if (r.plan.states.size() > keep) {
    r.plan.states.resize(keep);
    r.steps = k;
    r.reached_goal = false;
  }
  last_plan_ = r.plan;
  plan_start_steps_ = controller.steps_done;
  // After a restart the sequence goes on from the plan the robot walks.
  plan_seq_ = std::max(plan_seq_, controller.plan_seq) + 1;
  answer_ = transport::ToContactPlanMsg(r.plan, Now(), path_request_id_, path_terrain_id_, plan_seq_, msg.utime);
  // Along a path that ends short of the goal (the map does not show it yet) no plan reaches it.
  answer_->reaches_goal = answer_->reaches_goal && path_reaches_goal_;
  answer_wall_ = std::chrono::steady_clock::now();
  lcm_.publish(options_.contact_plan_channel, &*answer_);
  status_.Ok(Now(), msg.utime, ms, "plan " + std::to_string(plan_seq_) + ": " + Summary(r, k));
  PlanAhead(controller.steps_committed);
}

bool ContactPlannerNode::ResendAnswerIfDue() {
  if (!(options_.resend_period_s > 0.0) || !answer_) return false;
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - answer_wall_).count() < options_.resend_period_s) return false;
  answer_wall_ = now;
  lcm_.publish(options_.contact_plan_channel, &*answer_);
  return true;
}

bool ContactPlannerNode::ResendIfStillAwaited(const rbcp_msgs::controller_status_t& state) {
  if (!answer_ || answer_->start_utime < state.awaiting_since || !ResendAnswerIfDue()) return false;
  if (verbose_) {
    std::fprintf(stderr, "[%s] plan %lld sent again: the robot still waits at utime %lld\n", kProcessName,
                 static_cast<long long>(answer_->plan_seq), static_cast<long long>(state.awaiting_since));
  }
  return true;
}

int ContactPlannerNode::SearchSteps() const { return path_reaches_goal_ ? WholeSearchSteps() : PartialSearchSteps(); }

int ContactPlannerNode::WholeSearchSteps() const { return options_.horizon_steps + options_.lookahead_steps; }

int ContactPlannerNode::PartialSearchSteps() const {
  return options_.horizon_steps + std::min(options_.lookahead_steps, options_.partial_lookahead_steps);
}

void ContactPlannerNode::DropPlanAhead() {
  plan_made_ahead_.reset();
  search_ahead_.reset();  // a search still running goes on; its answer is dropped
}

void ContactPlannerNode::WaitForSearchWorker() {
  if (search_worker_.valid()) search_worker_.get();
}

bool ContactPlannerNode::SearchWorkerBusy() const {
  return search_worker_.valid() && search_worker_.wait_for(std::chrono::seconds(0)) != std::future_status::ready;
}

void ContactPlannerNode::PlanAhead(int steps_committed) {
  if (!options_.plan_ahead || !last_plan_ || last_plan_->states.size() < 2) return;
  plan_ahead_terrain_id_ = world_.terrain_id();
  if (last_plan_->reaches_goal && last_plan_->states.size() == 2) return;  // the last step: nothing after it
  SearchAhead search;
  search.next.after_plan_seq = plan_seq_;
  search.next.expected = last_plan_->states[1];
  double offset_xy = 0.0;
  search.next.progress = PathProgress(search.next.expected.base_position, search.next.expected.base_rpy.z(), &offset_xy);
  // The search the plan came from goes on beyond the next step: its continuation. The steps after
  // the next one that the controller's motion already prepares for (a dynamic walk's preview) stay
  // as they are; a new search starts after them (K steps and the look-ahead deep). When it fails,
  // or its K steps get the trunk less far along the path than the continuation's, the earlier
  // search goes on. New searches at every step could otherwise choose differently each time and
  // re-place the feet back and forth without the trunk getting anywhere.
  ContactPlan continuation;
  continuation.states.assign(searched_.states.begin() + 1, searched_.states.end());
  continuation.states.front().MarkAsStart();
  continuation.reaches_goal = searched_.reaches_goal;
  const int after_next = static_cast<int>(continuation.states.size()) - 1;
  search.kept = std::clamp(steps_committed, 0, after_next);
  const int kept = search.kept;
  const bool timed = continuation.Timed();
  const bool goal_committed = kept == after_next && continuation.reaches_goal;
  // The new search runs on its own planner while the robot walks; it starts from the stance the
  // kept steps lead to, with the leg that stepped into it (the crawl's order goes on from there).
  const bool worker_busy = SearchWorkerBusy() && !options_.wait_for_search_ahead;
  if (!goal_committed && !worker_busy) {
    WaitForSearchWorker();
    const WholeBodyState& from = searched_.states[static_cast<std::size_t>(kept) + 1];
    double offset = 0.0;
    const std::size_t at = PathProgress(from.base_position, from.base_rpy.z(), &offset);
    std::vector<RootPathSample> remaining(path_.begin() + static_cast<std::ptrdiff_t>(at), path_.end());
    // The new search's plan begins with the committed steps, as the earlier search made them.
    std::vector<WholeBodyState> committed(continuation.states.begin(), continuation.states.begin() + kept + 1);
    const int max_steps = SearchSteps();
    search_worker_ = std::async(std::launch::async, [planner = &ahead_planner_, kept, timed, from,
                                                     committed = std::move(committed), remaining = std::move(remaining),
                                                     max_steps] {
      SearchAheadAnswer answer;
      try {
        answer.result = planner->PlanHorizon(from, remaining, max_steps);
        ContactPlanResult& fresh = *answer.result;
        if (fresh.ok && kept > 0) {
          // The committed steps, then the new search's, timed again with the committed steps'
          // durations kept.
          std::vector<WholeBodyState> states = committed;
          states.insert(states.end(), fresh.plan.states.begin() + 1, fresh.plan.states.end());
          fresh.plan.states = std::move(states);
          fresh.steps = static_cast<int>(fresh.plan.states.size()) - 1;
          planner->TimeWalk(&fresh.plan, &fresh.stats, timed ? kept : 0);
        }
      } catch (const std::exception& e) {
        answer.result.reset();
        answer.error = e.what();
      }
      return answer;
    });
    search.running = true;
  }
  // The earlier search's steps, on the clock the walk prepared for: their durations stay. Timed
  // here while the new search runs.
  planner_.TimeWalk(&continuation, nullptr, timed ? after_next : 0);
  search.continuation = std::move(continuation);
  if (goal_committed) {
    return TakeEarlierSearch(std::move(search), "the search before reaches the goal within the committed steps");
  }
  if (worker_busy && verbose_) {
    std::fprintf(stderr, "[%s] planning ahead: the search before is still running\n", kProcessName);
  }
  search_ahead_ = std::move(search);  // without a new search, answered by the earlier one at the boundary
}

void ContactPlannerNode::TakeEarlierSearch(SearchAhead search, const std::string& how) {
  PlanMadeAhead next = std::move(search.next);
  next.result = ContactPlanResult{};
  next.result.ok = true;
  next.result.status = ContactPlanStatus::kOk;
  next.result.reached_goal = search.continuation.reaches_goal;
  next.result.steps = static_cast<int>(search.continuation.states.size()) - 1;
  next.result.plan = std::move(search.continuation);
  if (verbose_) {
    std::fprintf(stderr, "[%s] planned ahead: %s (%d steps after the next one)\n", kProcessName, how.c_str(),
                 next.result.steps);
  }
  plan_made_ahead_ = std::move(next);
}

void ContactPlannerNode::FinishPlanAhead() {
  if (!search_ahead_) return;
  SearchAhead search = std::move(*search_ahead_);
  search_ahead_.reset();
  const int after_next = static_cast<int>(search.continuation.states.size()) - 1;
  if (!search.running || (SearchWorkerBusy() && !options_.wait_for_search_ahead)) {
    // The robot is at the boundary and the new search has not ended (or could not start): the
    // earlier search goes on, with no wait.
    if (after_next < 1) return;
    return TakeEarlierSearch(std::move(search), search.running ? "the new search has not ended; the search before goes on"
                                                               : "no new search; the search before goes on");
  }
  SearchAheadAnswer answer = search_worker_.get();
  if (!answer.result) {
    if (verbose_) std::fprintf(stderr, "[%s] planning ahead failed: %s\n", kProcessName, answer.error.c_str());
    return;
  }
  ContactPlanResult& fresh = *answer.result;
  if (verbose_) {
    std::fprintf(stderr, "[%s] planned ahead from the stance %d step(s) after the next: %s in %.3f s\n", kProcessName,
                 search.kept, fresh.ok ? "ok" : fresh.reason.c_str(), fresh.planning_time_s);
  }
  const auto progress = [&](const WholeBodyState& s) {
    double offset = 0.0;
    return PathProgress(s.base_position, s.base_rpy.z(), &offset);
  };
  if (KeepEarlierSearch(search.continuation, fresh, options_.horizon_steps, options_.reuse_margin_steps, progress)) {
    const bool ok = fresh.ok;
    return TakeEarlierSearch(std::move(search), ok ? "the new plan gets less far; the search before goes on"
                                                   : "no new plan; the search before goes on");
  }
  if (!fresh.ok) return;
  search.next.result = std::move(fresh);
  plan_made_ahead_ = std::move(search.next);
}

std::optional<RejectedInput> ContactPlannerNode::ToSamples(const rbcp_msgs::root_path_t& msg,
                                                           std::vector<RootPathSample>* samples) const {
  try {
    *samples = transport::FromRootPathMsg(msg, options_.max_path_duration_s);
  } catch (const InputError& e) {
    return RejectedInput::Content(e.what());
  }
  for (std::size_t i = 0; i < samples->size(); ++i) {
    const RootPathSample& s = (*samples)[i];
    const std::string what = "root path: point " + std::to_string(i);
    const Eigen::Vector2d xy = s.p.head<2>();
    if ((xy.array() < terrain_min_xy_.array() - kTerrainMargin_m).any() ||
        (xy.array() > terrain_max_xy_.array() + kTerrainMargin_m).any()) {
      std::ostringstream os;
      os << what << " at (" << xy.x() << ", " << xy.y() << ") is off the terrain (x in [" << terrain_min_xy_.x() << ", "
         << terrain_max_xy_.x() << "], y in [" << terrain_min_xy_.y() << ", " << terrain_max_xy_.y() << "])";
      return RejectedInput::Content(os.str());
    }
  }
  // The robot stands at the path start: there must be terrain below it (elsewhere the trunk may
  // pass over gaps with its feet on either side).
  const Eigen::Vector2d start = samples->front().p.head<2>();
  if (!TerrainHeightAt(*world_.terrain(), start)) {
    std::ostringstream os;
    os << "root path: the start (" << start.x() << ", " << start.y() << ") is not above the terrain";
    return RejectedInput::Content(os.str());
  }
  return std::nullopt;
}

void ContactPlannerNode::Plan(const rbcp_msgs::root_path_t& msg) {
  std::vector<RootPathSample> samples;
  if (auto problem = ToSamples(msg, &samples)) {
    last_result_.reset();
    status_.Failed(Now(), msg.utime, 0.0, problem->Describe());
    return;
  }
  // The root planner repeats its path for late processes, and to answer a repeated request: the
  // plan of it went out already, and goes out again (at most every resend_period_s) for a
  // process that missed it. A failure stays on STATUS.
  if (IsRepeat(msg, samples)) {
    if (answer_ && answer_->request_id == msg.request_id) ResendAnswerIfDue();
    return;
  }
  status_.Busy(Now(), msg.utime);
  answer_.reset();
  path_ = samples;
  path_request_id_ = msg.request_id;
  path_terrain_id_ = msg.terrain_id;
  try {
    if (verbose_) {
      std::fprintf(stderr, "[%s] planning the whole root path (request %lld): %zu points, %.2f s\n", kProcessName,
                   static_cast<long long>(msg.request_id), samples.size(), samples.back().t - samples.front().t);
    }
    last_result_ = planner_.Plan(samples);
  } catch (const std::exception& e) {
    last_result_.reset();
    status_.Failed(Now(), msg.utime, 0.0, std::string("internal error: ") + e.what());
    return;
  }
  const ContactPlanResult& r = *last_result_;
  const double ms = 1000.0 * r.planning_time_s;
  if (!r.ok) {
    status_.Failed(Now(), msg.utime, ms, ToString(r.status) + ": " + r.reason);
    return;
  }
  plan_seq_ += 1;
  answer_ = transport::ToContactPlanMsg(r.plan, Now(), msg.request_id, msg.terrain_id, plan_seq_, 0);
  answer_->reaches_goal = answer_->reaches_goal && msg.reaches_goal;
  answer_wall_ = std::chrono::steady_clock::now();
  lcm_.publish(options_.contact_plan_channel, &*answer_);
  status_.Ok(Now(), msg.utime, ms, Summary(r, 0));
}

void ContactPlannerNode::Heartbeat() { status_.Heartbeat(Now()); }

LimbDatabase LoadLimbDatabase(const RobotModel& robot, const std::string& config_dir, bool log) {
  const auto config = LimbDatabaseConfig::LoadFile(config_dir + "/limb_database.yaml");
  if (log) {
    std::fprintf(stderr, "[%s] limb database: %d samples per leg, reading the cache in %s (a first build takes some seconds)\n",
                 ContactPlannerNode::kProcessName, config.samples_per_leg, config.ResolvedCacheDir().c_str());
  }
  const auto start = std::chrono::steady_clock::now();
  LimbDatabaseCacheReport report;
  LimbDatabase database = LimbDatabase::LoadOrBuild(robot, LimbDatabase::DefaultRobotFiles(config_dir), config, &report);
  if (log) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double mb = static_cast<double>(database.MemoryBytes()) / (1024.0 * 1024.0);
    if (report.loaded) {
      std::fprintf(stderr, "[%s] limb database: loaded %s in %.2f s (%.1f MB)\n", ContactPlannerNode::kProcessName,
                   report.cache_path.c_str(), s, mb);
    } else {
      std::fprintf(stderr, "[%s] limb database: built in %.2f s (%.1f MB; %s)\n", ContactPlannerNode::kProcessName, s,
                   mb, report.rebuild_reason.c_str());
      if (report.write_error.empty()) {
        std::fprintf(stderr, "[%s] limb database: cached in %s\n", ContactPlannerNode::kProcessName,
                     report.cache_path.c_str());
      } else {
        std::fprintf(stderr, "[%s] limb database: not cached: %s\n", ContactPlannerNode::kProcessName,
                     report.write_error.c_str());
      }
    }
  }
  return database;
}

}  // namespace rbcp::nodes
