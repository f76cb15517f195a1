#include "rbcp/nodes/root_planner_node.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/nodes/contact_planner_node.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/plan_requests.h"

namespace rbcp::nodes {
namespace {

/// Places remembered at most (partial_map: where the robot waited, the dead ends); the oldest go.
constexpr std::size_t kMaxPlaces = 1000;

void Remember(std::vector<Eigen::Vector2d>* places, const Eigen::Vector2d& xy) {
  if (places->size() >= kMaxPlaces) places->erase(places->begin());
  places->push_back(xy);
}

/// A contact planner's answer that no contact plan follows the path: a planning query that failed
/// along it (FailedAlongPath; its reason starts "<status>:"), not a rejected input.
bool IsContactPlanningFailure(const rbcp_msgs::process_status_t& s) {
  if (s.process != ContactPlannerNode::kProcessName || s.state != rbcp_msgs::process_status_t::FAILED) return false;
  for (const ContactPlanStatus status : kContactPlanStatuses) {
    if (FailedAlongPath(status) && s.reason.rfind(ToString(status) + ":", 0) == 0) return true;
  }
  return false;
}

double YawOf(const double q[4]) {  // (w, x, y, z), base to world
  return std::atan2(2.0 * (q[0] * q[3] + q[1] * q[2]), 1.0 - 2.0 * (q[2] * q[2] + q[3] * q[3]));
}

}  // namespace

RootPlannerNode::RootPlannerNode(lcm::LCM& lcm, const RobotModel& robot, RootPlannerConfig config,
                                 RootPlannerNodeOptions options)
    : lcm_(lcm),
      options_(std::move(options)),
      planner_(robot, std::move(config)),
      request_(lcm, options_.request_channel),
      robot_state_(lcm, options_.robot_state_channel),
      controller_(lcm, options_.controller_status_channel),
      contact_failure_(lcm, options_.status_channel, IsContactPlanningFailure),
      world_(lcm, options_.terrain_channel, options_.affordances_channel),
      status_(lcm, kProcessName, options_.status_channel) {}

int64_t RootPlannerNode::Now() const { return clock_.Now(); }

std::optional<RejectedInput> RootPlannerNode::TakeInputs() {
  if (auto e = request_.TakeDecodeError()) return RejectedInput::Undecodable(std::move(*e));
  if (auto e = robot_state_.TakeDecodeError()) return RejectedInput::Undecodable(std::move(*e));
  if (auto e = controller_.TakeDecodeError()) return RejectedInput::Undecodable(std::move(*e));
  contact_failure_.TakeDecodeError();  // STATUS is every process's: another's bad message is not ours to report
  if (const auto& state = robot_state_.Latest()) {
    if (auto bad = clock_.World(state->utime, options_.robot_state_channel)) {
      return RejectedInput::Time(std::move(*bad));
    }
  }
  if (auto e = world_.Take(&clock_)) return e;
  if (auto msg = request_.Take()) {
    if (auto bad = clock_.Input(msg->utime, options_.request_channel)) return RejectedInput::Time(std::move(*bad));
    if (auto problem = transport::CheckPlanRequest(*msg, options_.max_time_budget_s)) {
      return RejectedInput::Content(problem->Describe());
    }
    // The operator repeats its request when an answer got lost, or for a restarted planner: a
    // repeat of the request already handled is answered again, and one still pending stays so.
    if (pending_ && transport::SameRequest(*pending_, *msg)) return std::nullopt;
    if (!pending_ && handled_ && transport::SameRequest(*handled_, *msg)) {
      repeat_due_ = true;
      return std::nullopt;
    }
    // Ids identify requests, they are not ordered: the latest new request is the goal, and a late
    // repeat of one given up since (its operator repeats it every second) is not.
    if (requests_taken_.Superseded(*msg)) return std::nullopt;
    requests_taken_.Take(*msg);
    pending_ = *msg;
    repeat_due_ = false;
    waiting_for_.clear();
  }
  return std::nullopt;
}

bool RootPlannerNode::Step() {
  if (auto rejected = TakeInputs()) {
    status_.Failed(Now(), Now(), 0.0, rejected->Describe());
    return true;
  }
  // A change is kept until a replan check or a plan sees it: a repeated request answered first
  // must not hide it.
  if (world_.TakeChanged()) world_changed_ = true;
  if (std::exchange(repeat_due_, false)) {
    AnswerAgain();
    return true;
  }
  if (!world_.Ready()) return ReportWaiting("waiting for " + world_.terrain_channel() + " and " + world_.affordances_channel());
  if (!pending_) {
    const std::optional<std::string> why = ReplanReason(std::exchange(world_changed_, false));
    if (!why) return false;
    rbcp_msgs::plan_request_t again = *active_;
    // Before its first step the robot stands at the request's start (within
    // replan_path_offset_m): the next guide starts there too, as a whole plan's next guide does.
    again.use_start = active_->use_start && StandsAtStart(*active_);
    PlanHandled(again, *why, /*replan=*/true);
    return true;
  }
  if (!pending_->use_start && !robot_state_.Latest()) {
    return ReportWaiting("waiting for " + options_.robot_state_channel + ": the request starts where the robot stands");
  }
  if (options_.partial_map && !WaitsOnItsMap()) {
    // A growing map is planned on as it stood when the robot waits (terrain_mapper sends that map):
    // the path then depends on the clouds up to the wait, not on when the request came.
    return ReportWaiting("waiting for the robot to wait at a step boundary and for the map of that wait");
  }
  rbcp_msgs::plan_request_t request = *pending_;
  pending_.reset();
  if (!active_ || active_->request_id != request.request_id) {  // a new goal
    visited_.clear();
    dead_ends_.clear();
  }
  waiting_for_.clear();
  handled_ = request;
  guide_ = 0;
  std::string why;
  if (request.use_start) {
    // A request to start where the robot no longer stands (the robot walked on while this
    // process was restarted) is planned from where it stands.
    const std::optional<double> off = DistanceFromStart(request);
    if (off && *off > options_.replan_path_offset_m) {
      request.use_start = false;
      why = "the robot stands " + FixedNumber(*off, 2) + " m from the requested start";
    }
  }
  PlanHandled(request, why);
  return true;
}

bool RootPlannerNode::ReportWaiting(const std::string& what) {
  if (!pending_ || what == waiting_for_) return false;
  waiting_for_ = what;
  status_.Waiting(Now(), pending_->utime, what);
  return true;
}

void RootPlannerNode::AnswerAgain() {
  if (handled_failure_) {
    status_.Failed(Now(), handled_->utime, 0.0, *handled_failure_);
  } else if (published_) {
    lcm_.publish(options_.root_path_channel, &*published_);
  }
}

void RootPlannerNode::PlanHandled(const rbcp_msgs::plan_request_t& request, const std::string& why, bool replan) {
  Plan(request, why, replan);
  const rbcp_msgs::process_status_t answer = status_.last();
  // A replan that failed leaves the request its previous path: that is its answer.
  if (answer.state == rbcp_msgs::process_status_t::FAILED && !published_) handled_failure_ = answer.reason;
  else handled_failure_.reset();
}

std::optional<double> RootPlannerNode::DistanceFromStart(const rbcp_msgs::plan_request_t& request) const {
  if (!robot_state_.Latest()) return std::nullopt;
  const auto& state = *robot_state_.Latest();
  const Eigen::Vector2d base(state.base_position[0], state.base_position[1]);
  if (!base.allFinite()) return std::nullopt;
  return (base - Eigen::Vector2d(request.start_position[0], request.start_position[1])).norm();
}

bool RootPlannerNode::StandsAtStart(const rbcp_msgs::plan_request_t& request) const {
  if (!controller_.Latest() || controller_.Latest()->steps_done > 0) return false;
  const std::optional<double> off = DistanceFromStart(request);
  return off && *off <= options_.replan_path_offset_m;
}

bool RootPlannerNode::WaitsOnItsMap() const {
  const auto& state = robot_state_.Latest();
  const auto& controller = controller_.Latest();
  return state && controller && controller->awaiting_plan && state->utime >= controller->awaiting_since &&
         world_.terrain_utime() >= controller->awaiting_since;
}

bool RootPlannerNode::KeepPathOnNewMap(const rbcp_msgs::robot_state_t& state) {
  if (!last_result_ || !last_result_->ok() || !published_ || !active_) return false;
  const auto& samples = last_result_->samples;
  const Eigen::Vector2d base(state.base_position[0], state.base_position[1]);
  if (!base.allFinite() || samples.empty()) return false;
  std::size_t nearest = 0;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    if ((samples[i].p.head<2>() - base).norm() < (samples[nearest].p.head<2>() - base).norm()) nearest = i;
  }
  try {
    const TriangleMesh& terrain = *world_.terrain();
    const std::vector<AffordanceSurface>& surfaces = *world_.surfaces();
    if (!last_reaches_goal_) {
      // At the end of a path short of the goal the robot needs a new one, whatever the map shows.
      if ((samples.back().p.head<2>() - base).norm() <= options_.replan_path_offset_m) return false;
      // A path short of the goal is planned again when the map shows a way much nearer it.
      const Eigen::Vector2d goal(active_->goal_position[0], active_->goal_position[1]);
      const std::vector<Eigen::Vector3d> goals =
          planner_.GoalsToward(terrain, surfaces, base, goal, active_->goal_yaw, options_.partial_goals, dead_ends_);
      const double now_left = (samples.back().p.head<2>() - goal).norm();
      if (!goals.empty()) {
        const double then_left = (goals.front().head<2>() - goal).norm();
        if (then_left < 1e-9 || now_left - then_left >= options_.partial_replan_gain_m) return false;  // the goal, or much nearer
      }
    }
    // The rest of the path must hold on the new map.
    ReachabilityChecker checker = planner_.MakeChecker(terrain, surfaces);
    for (std::size_t i = nearest; i < samples.size(); ++i) {
      if (!checker.IsValid(samples[i].p, samples[i].yaw)) return false;
    }
  } catch (const InputError&) {
    return false;
  }
  // The same path, now the path on this map.
  published_->terrain_id = world_.terrain_id();
  published_->utime = Now();
  lcm_.publish(options_.root_path_channel, &*published_);
  return true;
}

std::optional<std::string> RootPlannerNode::ReplanReason(bool world_changed) {
  if (!active_) return std::nullopt;
  // On a growing map a request without a path is planned again on the next map.
  if (!options_.partial_map && (!last_result_ || !last_result_->ok())) return std::nullopt;
  if (world_changed) terrain_replan_due_ = true;  // a path planned on another terrain
  if (!robot_state_.Latest() || !controller_.Latest()) return std::nullopt;
  const auto& state = *robot_state_.Latest();
  const auto& controller = *controller_.Latest();
  // Replans start where the robot stands at a step boundary: the world stands still there (the
  // robot waits for a plan), so the new path does not depend on when this process heard of it.
  if (!controller.awaiting_plan || state.utime < controller.awaiting_since) return std::nullopt;
  // A growing map is planned on as it stood at the wait (terrain_mapper sends that one).
  if (options_.partial_map && world_.terrain_utime() < controller.awaiting_since) return std::nullopt;
  if (guide_stance_ != controller.steps_done) {  // the robot walked on since the last guide
    guide_stance_ = controller.steps_done;
    guides_this_stance_ = 0;
  }
  // The contact planner found no plan along this path for this wait: the next guide.
  if (const auto& failed = contact_failure_.Latest();
      failed && failed->input_utime >= controller.awaiting_since &&
      failure_acted_ != std::make_pair(failed->pid, failed->handled)) {
    failure_acted_ = std::make_pair(failed->pid, failed->handled);
    if (guides_this_stance_ < planner_.config().guide_retries) {
      ++guides_this_stance_;
      ++guide_;
      return "no contact plan follows the previous path (" + failed->reason.substr(0, 160) + "): guide " +
             std::to_string(guide_ + 1);
    }
  }
  if (terrain_replan_due_) {
    terrain_replan_due_ = false;
    checked_wait_ = controller.awaiting_since;
    // A map that grew: the path the robot follows goes on while it holds on the new map and the
    // map shows no way much nearer the goal.
    if (options_.partial_map && KeepPathOnNewMap(state)) return std::nullopt;
    return "the terrain changed";
  }
  if (checked_wait_ == controller.awaiting_since || !last_result_ || !last_result_->ok()) return std::nullopt;
  checked_wait_ = controller.awaiting_since;
  const Eigen::Vector2d base(state.base_position[0], state.base_position[1]);
  if (!base.allFinite()) return std::nullopt;
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& s : last_result_->samples) nearest = std::min(nearest, (s.p.head<2>() - base).norm());
  if (nearest <= options_.replan_path_offset_m) return std::nullopt;
  return "the robot stands " + FixedNumber(nearest, 2) + " m from the path";
}

void RootPlannerNode::Plan(const rbcp_msgs::plan_request_t& request, const std::string& why, bool replan) {
  status_.Busy(Now(), request.utime);
  // A replan that fails leaves the path the robot follows as it is: the loop goes on along it
  // (the contact planner plans from where the robot stands; its next failure asks for the next
  // guide). A new request's failure leaves no path.
  const bool keep = replan && last_result_ && last_result_->ok() && published_;
  const auto failed = [&](double ms, const std::string& reason) {
    if (!keep) {
      last_result_.reset();
      published_.reset();
    }
    // On a growing map the request stays active: the next map may show the way. A path kept is
    // sent again as the path on this map, so that the contact planner plans along it on the map
    // of this wait.
    if (options_.partial_map) {
      active_ = request;
      if (keep) {
        published_->terrain_id = world_.terrain_id();
        published_->utime = Now();
        lcm_.publish(options_.root_path_channel, &*published_);
      }
    }
    status_.Failed(Now(), request.utime, ms, reason + (keep ? " (the robot goes on along the previous path)" : ""));
  };
  terrain_replan_due_ = world_changed_ = false;  // planned on the terrain as it is now
  Eigen::Vector2d start_xy(request.start_position[0], request.start_position[1]);
  double start_yaw = request.start_yaw;
  if (!request.use_start) {
    const auto& state = *robot_state_.Latest();
    start_xy = {state.base_position[0], state.base_position[1]};
    start_yaw = YawOf(state.base_orientation);
    if (!start_xy.allFinite() || !std::isfinite(start_yaw)) return failed(0.0, "robot state: base pose is not finite");
  }
  // A requested start stands on the terrain at its xy. The measured base is where the robot is, at
  // the height it stands at: over the edge of a block with its fore feet up and its hind feet on
  // the floor it stands lower than the block's top plus the nominal height, where its hind legs
  // would not reach the floor. One inside the terrain is not lifted onto its top.
  std::optional<Eigen::Vector3d> measured_base;
  if (!request.use_start) {
    const auto& state = *robot_state_.Latest();
    const Eigen::Vector3d base(state.base_position[0], state.base_position[1], state.base_position[2]);
    std::optional<std::string> problem;
    if (!base.allFinite()) {
      problem = "robot state: base pose is not finite";
    } else if (auto bad = planner_.CheckMeasuredBase(*world_.terrain(), base)) {
      problem = bad->Describe();
    }
    if (problem) return failed(0.0, "start_invalid: " + *problem);
    measured_base = base;
  }
  RootPlanResult result;
  try {
    const Eigen::Vector2d goal_xy(request.goal_position[0], request.goal_position[1]);
    const std::optional<Eigen::Vector3d> start =
        measured_base ? measured_base : planner_.StandingPosition(*world_.terrain(), start_xy);
    RootPlanRequest query;
    query.start_yaw = start_yaw;
    query.time_budget_s = request.time_budget > 0.0 ? request.time_budget : options_.default_time_budget_s;
    query.seed = GuideSeed(static_cast<unsigned>(request.seed), guide_);
    query.start_is_measured = measured_base.has_value();
    if (start) query.start.p = *start;
    if (options_.partial_map) {
      if (!start) return failed(0.0, "no terrain under the start on the map");
      // The goal, or the standing positions nearest it on the known terrain, until one has a path.
      std::vector<Eigen::Vector3d> goals =
          planner_.GoalsToward(*world_.terrain(), *world_.surfaces(), start_xy, goal_xy, request.goal_yaw,
                               options_.partial_goals, dead_ends_);
      // None nearer the goal (a wall, a dead end): the edge of the map where the robot has not
      // stood yet, for its cameras to see the way on; and this place is no way nearer the goal.
      Remember(&visited_, start_xy);
      exploring_ = goals.empty();
      if (exploring_) {
        goals = planner_.FrontierGoals(*world_.terrain(), *world_.surfaces(), goal_xy, visited_, options_.partial_goals);
        Remember(&dead_ends_, start_xy);
      }
      if (goals.empty()) return failed(0.0, "the map shows no standing position nearer the goal yet, nor an edge of the map the robot has not stood at");
      // The candidates share one query's RRT iterations (each the rest of them over the candidates
      // left), so a map that shows no way costs the waiting robot one search, not one per
      // candidate, and the path depends on the map and the seed only. The request's time budget
      // stays the safety limit of them all.
      const double budget = query.time_budget_s;
      const int iterations = planner_.config().max_iterations;
      double spent = 0.0;
      int used = 0;
      for (std::size_t i = 0; i < goals.size(); ++i) {
        last_reaches_goal_ = (goals[i].head<2>() - goal_xy).norm() < 1e-9;
        const Eigen::Vector2d way = goal_xy - goals[i].head<2>();  // at a partial goal the robot faces the goal
        const double yaw = last_reaches_goal_ ? request.goal_yaw : std::atan2(way.y(), way.x());
        query.goal = goals[i];
        query.goal_yaw = yaw;
        query.max_iterations = std::max(1, (iterations - used) / static_cast<int>(goals.size() - i));
        query.time_budget_s = std::max(1e-3, budget - spent);
        result = planner_.Plan(*world_.terrain(), *world_.surfaces(), query);
        spent += result.planning_time_s;
        used += result.iterations;
        // A candidate the search cannot reach (the map between is not known well enough): the next.
        if (result.ok() || result.status == RootPlanStatus::kInvalidInput || result.status == RootPlanStatus::kStartInvalid) {
          break;
        }
      }
      result.planning_time_s = spent;
    } else {
      const auto goal = planner_.StandingPosition(*world_.terrain(), goal_xy);
      if (!start || !goal) return failed(0.0, std::string("no terrain under the ") + (start ? "goal" : "start"));
      last_reaches_goal_ = true;
      query.goal = *goal;
      query.goal_yaw = request.goal_yaw;
      result = planner_.Plan(*world_.terrain(), *world_.surfaces(), query);
    }
  } catch (const std::exception& e) {
    // A request the planner refuses is answered with a status (below). What it throws is a
    // terrain or surfaces its reachability checker cannot be built on (InputError), or a bug
    // (InvariantError): either fails this request, not the process.
    return failed(0.0, std::string("cannot plan: ") + e.what());
  }
  const double ms = 1000.0 * result.planning_time_s;
  if (!result.ok()) return failed(ms, ToString(result.status) + ": " + result.reason);
  last_result_ = std::move(result);
  published_ = ToRootPathMsg(*last_result_, Now(), request.request_id, world_.terrain_id(), last_reaches_goal_);
  lcm_.publish(options_.root_path_channel, &*published_);
  active_ = request;
  std::string summary = why.empty() ? "" : "replanned from the measured base: " + why;
  if (last_result_->start_join_m > 0.0) {
    summary += std::string(summary.empty() ? "" : "; ") + "the path joins the measured base to the nearest start " +
               "that satisfies the reachability condition, " + FixedNumber(last_result_->start_join_m, 2) + " m away";
  }
  if (!last_reaches_goal_) {
    const Eigen::Vector3d end = last_result_->samples.back().p;
    summary += std::string(summary.empty() ? "" : "; ") + "towards the goal, to (" + FixedNumber(end.x(), 2) + ", " +
               FixedNumber(end.y(), 2) + "), " +
               (exploring_ ? "an edge of the map (the known terrain shows no way nearer the goal)"
                           : "the known terrain's nearest standing position");
  }
  status_.Ok(Now(), request.utime, ms, summary);
}

void RootPlannerNode::Heartbeat() {
  status_.Heartbeat(Now());
  // The current path again, unchanged, for a contact planner that started after it went out.
  if (published_ && last_result_ && last_result_->ok()) lcm_.publish(options_.root_path_channel, &*published_);
}

rbcp_msgs::root_path_t ToRootPathMsg(const RootPlanResult& result, int64_t utime, int64_t request_id,
                                     int64_t terrain_id, bool reaches_goal) {
  rbcp_msgs::root_path_t msg;
  msg.utime = utime;
  msg.request_id = request_id;
  msg.terrain_id = terrain_id;
  msg.reaches_goal = reaches_goal;
  msg.num_points = static_cast<int32_t>(result.samples.size());
  for (const auto& s : result.samples) {
    rbcp_msgs::root_path_point_t p;
    p.t = s.t;
    for (int k = 0; k < 3; ++k) {
      p.position[k] = s.p[k];
      p.velocity[k] = s.v[k];
    }
    p.orientation[0] = std::cos(0.5 * s.yaw);
    p.orientation[1] = 0.0;
    p.orientation[2] = 0.0;
    p.orientation[3] = std::sin(0.5 * s.yaw);
    msg.points.push_back(p);
  }
  return msg;
}

}  // namespace rbcp::nodes
