#include "rbcp/contact_planner/contact_planner.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "merge_steps.h"
#include "path_track.h"
#include "planner_context.h"
#include "rbcp/affordance/surface_graph.h"
#include "rbcp/collision/robot_terrain_collision.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/static_equilibrium.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/stance/dynamic_walk.h"
#include "search.h"
#include "search_node.h"
#include "stance_checks.h"
#include "start_stance.h"
#include "step.h"
#include "surface_geometry.h"

namespace rbcp {

using contact_planner_detail::AvoidedStep;
using contact_planner_detail::ConvexPolygon3d;
using contact_planner_detail::kNoMargins;
using contact_planner_detail::Node;
using contact_planner_detail::PathBasePose;
using contact_planner_detail::PathPose;
using contact_planner_detail::PathTrack;
using contact_planner_detail::PlannerContext;
using contact_planner_detail::SearchWithRetries;
using contact_planner_detail::SolveStance;
using contact_planner_detail::StandingAt;
using contact_planner_detail::StandingFailure;
using contact_planner_detail::StandingResult;
using contact_planner_detail::TimeBudget;
using contact_planner_detail::Yaw;

std::string ToString(ContactPlanStatus status) {
  switch (status) {
    case ContactPlanStatus::kOk: return "ok";
    case ContactPlanStatus::kInvalidInput: return "invalid_input";
    case ContactPlanStatus::kNoStartStance: return "no_start_stance";
    case ContactPlanStatus::kNoFoothold: return "no_foothold";
    case ContactPlanStatus::kGoalUnreachable: return "goal_unreachable";
    case ContactPlanStatus::kTimeout: return "timeout";
  }
  return "unknown";
}

bool FailedAlongPath(ContactPlanStatus status) {
  return status == ContactPlanStatus::kNoFoothold || status == ContactPlanStatus::kTimeout;
}

namespace {

/// Interpolation step of a RootPath handed to Plan() [s].
constexpr double kRootPathSampling = 0.01;

/// Steps of `checks` whose dynamic walk fails its check.
int FailingSteps(const std::vector<DynamicStepCheck>& checks) {
  return static_cast<int>(std::count_if(checks.begin(), checks.end(), [](const auto& c) { return !c.verdict.ok(); }));
}

/// Steps of `checks` that TimeDynamicWalk slowed.
int SlowedSteps(const std::vector<DynamicStepCheck>& checks) {
  return static_cast<int>(std::count_if(checks.begin(), checks.end(), [](const auto& c) { return c.slowdowns > 0; }));
}

/// A failure of a foot out of reach or of the robot on the terrain, which no pace cures.
bool IsGeometric(StanceCheck check) {
  return check == StanceCheck::kReach || check == StanceCheck::kCollision || check == StanceCheck::kSwingTerrain;
}

/// How badly a plan's dynamic walk fails, worst first: steps out of reach or on the terrain, then
/// all failing steps (torque, balance and support have margins).
std::pair<int, int> WalkFailures(const std::vector<DynamicStepCheck>& checks) {
  const int geometric = static_cast<int>(
      std::count_if(checks.begin(), checks.end(), [](const auto& c) { return IsGeometric(c.verdict.check); }));
  return {geometric, FailingSteps(checks)};
}

/// The step of `plan` to blame for the failure of state `index`'s dynamic walk: with four feet
/// down (the shift before its swing), the step that put the leg out of reach or on the terrain
/// where it stands, if the plan made it, from any stance; else state `index`'s own step.
AvoidedStep WalkFailureStep(const ContactPlan& plan, std::size_t index, const StanceVerdict& verdict) {
  if (verdict.phase == StepPhase::kShift && verdict.leg) {
    for (std::size_t j = index - 1; j >= 1; --j) {
      if (plan.states[j].moving_leg == Index(*verdict.leg)) return AvoidedStep::Of(plan.states[j - 1], plan.states[j], false);
    }
  }
  return AvoidedStep::Of(plan.states[index - 1], plan.states[index]);
}

/// A plan of at least one step timed for the dynamic walk (TimeDynamicWalk); its steps slowed and
/// failing added to *stats (optional). Returns the steps' checks.
std::vector<DynamicStepCheck> TimeWalkOf(const StanceChecker& stance, ContactPlan* plan, ContactPlanStats* stats,
                                         int keep_steps = 0) {
  if (plan->states.size() < 2) return {};
  std::vector<DynamicStepCheck> checks = TimeDynamicWalk(stance, plan, keep_steps);
  if (stats != nullptr) {
    stats->walk_steps_slowed += SlowedSteps(checks);
    stats->walk_steps_failing += FailingSteps(checks);
  }
  return checks;
}

}  // namespace

struct ContactPlanner::Impl {
  const RobotModel& robot;
  const LimbDatabase& db;
  EquilibriumConfig eq_config;
  ContactPlannerConfig config;
  StaticEquilibrium equilibrium;
  // The LP workspaces of the searches on other threads (retry.parallel_searches - 1).
  std::vector<std::unique_ptr<StaticEquilibrium>> spare_equilibria;
  std::vector<StaticEquilibrium*> spare;
  StanceChecker stance;  // with the terrain's collision structures
  std::vector<ConvexPolygon3d> surfaces;
  std::vector<AvoidedStep> avoided;  // per query: steps whose dynamic walk failed (SearchFrom)
  std::unique_ptr<SurfaceGraph> surface_graph;
  std::optional<PlannerContext> context;  // all of the above, for the stages; set with the terrain

  // Per query.
  TimeBudget budget;
  ContactPlanStats stats;
  BodyPoseData body_poses;
  std::optional<PathTrack> path;

  Impl(const RobotModel& r, const LimbDatabase& d, const EquilibriumConfig& e, const ContactPlannerConfig& c,
       const StanceConfig& s)
      : robot(r), db(d), eq_config(e), config(c), equilibrium(r.TotalMass(), e), stance(r, StanceRules{s, e.friction}) {
    config.Validate();
    for (int k = 1; k < config.retry.parallel_searches; ++k) {
      spare_equilibria.push_back(std::make_unique<StaticEquilibrium>(r.TotalMass(), e));
      spare.push_back(spare_equilibria.back().get());
    }
  }

  const PlannerContext& ctx() const { return *context; }

  void SetTerrainContext() {
    context.emplace(
        PlannerContext{robot, db, eq_config, config, stance, surfaces, avoided, equilibrium, stats, budget, body_poses});
  }

  /// The answer to a query whose path ends where no surface in the feet's reach is joined,
  /// through surfaces each within max_surface_gap_m of the next, to a surface a start foot
  /// stands on; nullopt when one is (or when the start feet stand on no known surface).
  std::optional<ContactPlanResult> GoalUnreachableResult(const std::array<FootContact, kNumLegs>& start_feet) const {
    if (!surface_graph) return std::nullopt;
    std::vector<int> from, to;
    for (const FootContact& f : start_feet) {
      for (int s : surface_graph->SurfacesNear(f.position, 0.01)) from.push_back(s);
    }
    const FootWorkspace& ws = config.workspace;
    const double reach = Eigen::Vector3d(std::max(ws.max_forward_m, ws.max_backward_m),
                                         std::max(ws.max_outward_m, ws.max_inward_m), std::max(ws.max_up_m, ws.max_down_m))
                             .norm();
    const Eigen::Isometry3d end = PathBasePose(path->At(path->End()));
    for (Leg leg : kAllLegs) {
      for (int s : surface_graph->SurfacesNear(end * robot.ReferenceFootPosition(leg), reach)) to.push_back(s);
    }
    if (from.empty() || surface_graph->Joined(from, to)) return std::nullopt;
    ContactPlanResult result;
    result.status = ContactPlanStatus::kGoalUnreachable;
    result.reason = "no chain of contact surfaces, each within " + FixedNumber(config.max_surface_gap_m, 2) +
                    " m of the next, joins the start feet's surfaces to one in reach at the path's end";
    result.failure_time_s = path->Begin();
    result.planning_time_s = budget.Elapsed();
    result.stats = stats;
    return result;
  }

  void BeginQuery(std::vector<RootPathSample> samples) {
    budget.Start(config.time_budget_s);
    stats = ContactPlanStats{};
    path.emplace(std::move(samples), config.path_yaw_smoothing_s);
  }

  /// The search from `root` with the query's planning time and work counters. A plan whose
  /// dynamic walk puts a leg on the terrain or a foot out of reach is searched for again
  /// (retry.walk_searches times at most), each time also without the step blamed (WalkFailureStep)
  /// for the first such failure of the best plan found that is not avoided yet, collisions before
  /// reach; the answer is the plan that fails least (WalkFailures), the first found among equals.
  ContactPlanResult SearchFrom(const Node& root, int max_steps) {
    avoided.clear();
    std::vector<DynamicStepCheck> checks;
    ContactPlanResult result = SearchOnce(root, max_steps, &checks);
    for (int k = 0; k < config.retry.walk_searches && result.ok; ++k) {
      // A leg on the terrain first (the robot falls or a foot slides), then a foot out of reach
      // (the walk lags); torque, balance and support have margins and are not searched around.
      std::optional<AvoidedStep> blamed;
      for (const bool collision : {true, false}) {
        for (std::size_t i = 0; i < checks.size() && !blamed; ++i) {
          const StanceCheck c = checks[i].verdict.check;
          if (!IsGeometric(c) || (c != StanceCheck::kReach) != collision) continue;
          const AvoidedStep step = WalkFailureStep(result.plan, i + 1, checks[i].verdict);
          if (std::none_of(avoided.begin(), avoided.end(), [&](const AvoidedStep& a) { return a == step; })) blamed = step;
        }
      }
      if (!blamed) break;
      avoided.push_back(*blamed);
      ++stats.walk_searches;
      std::vector<DynamicStepCheck> again_checks;
      ContactPlanResult again = SearchOnce(root, max_steps, &again_checks);
      if (!again.ok) break;  // no plan without the steps avoided (or out of time)
      if (WalkFailures(again_checks) < WalkFailures(checks)) {
        result = std::move(again);
        checks = std::move(again_checks);
      }
    }
    result.planning_time_s = budget.Elapsed();
    const int merged = result.stats.steps_merged;  // the answer's, not every search's
    result.stats = stats;
    result.stats.steps_merged = merged;
    result.stats.walk_steps_slowed = SlowedSteps(checks);
    result.stats.walk_steps_failing = FailingSteps(checks);
    return result;
  }

  /// One search from `root` with the steps `avoided`: the plan found, merged (the steps merged in
  /// its stats.steps_merged), with its swings and timed for the dynamic walk (its steps' checks in
  /// *checks).
  ContactPlanResult SearchOnce(const Node& root, int max_steps, std::vector<DynamicStepCheck>* checks) {
    checks->clear();
    ContactPlanResult result = SearchWithRetries(ctx(), *path, root, max_steps, spare);
    result.stats.steps_merged = 0;
    if (result.ok && config.merge.enabled) {
      result.plan.states =
          contact_planner_detail::MergeSteps(ctx(), std::move(result.plan.states), &result.stats.steps_merged);
      result.steps = static_cast<int>(result.plan.states.size()) - 1;
    }
    if (result.ok) {
      contact_planner_detail::AttachSwings(ctx(), result.plan.states);
      *checks = TimeWalkOf(ctx().stance, &result.plan, nullptr);
    }
    return result;
  }

  /// Why `samples` cannot be planned along (or no terrain is set); nullopt when they can.
  std::optional<std::string> PathProblem(const std::vector<RootPathSample>& samples) const {
    if (samples.empty()) return "the root path has no sample";
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (!samples[i].p.allFinite() || !std::isfinite(samples[i].yaw) || !std::isfinite(samples[i].t)) {
        return "root path sample " + std::to_string(i) + " is not finite";
      }
      if (i > 0 && !(samples[i].t > samples[i - 1].t)) {
        return "root path times must increase (sample " + std::to_string(i) + ")";
      }
    }
    if (!stance.HasTerrain()) return "no terrain set";
    return std::nullopt;
  }
};

ContactPlanner::ContactPlanner(const RobotModel& robot, const LimbDatabase& database,
                               const EquilibriumConfig& equilibrium, const ContactPlannerConfig& config,
                               const StanceConfig& stance)
    : impl_(std::make_unique<Impl>(robot, database, equilibrium, config, stance)) {}
ContactPlanner::~ContactPlanner() = default;
ContactPlanner::ContactPlanner(ContactPlanner&&) noexcept = default;
ContactPlanner& ContactPlanner::operator=(ContactPlanner&&) noexcept = default;

void ContactPlanner::SetTerrain(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces) {
  if (terrain.triangles.empty()) throw InputError("contact planner: expected a terrain mesh, got no triangles");
  impl_->stance.SetTerrain(&terrain);
  impl_->surfaces.clear();
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const AffordanceSurface& s = surfaces[i];
    if (s.vertices.size() < 3 || !s.normal.allFinite() || s.normal.norm() < 1e-9) {
      throw InputError("contact surface " + std::to_string(i) + ": expected a polygon with >= 3 vertices and a normal");
    }
    impl_->surfaces.emplace_back(s.vertices, s.normal);
  }
  impl_->surface_graph = std::make_unique<SurfaceGraph>(surfaces, impl_->config.max_surface_gap_m);
  impl_->SetTerrainContext();
}

ContactPlanResult ContactPlanner::Plan(const RootPath& path) { return Plan(path.SampleEvery(kRootPathSampling)); }

ContactPlanResult ContactPlanner::Plan(const std::vector<RootPathSample>& samples) {
  Impl& m = *impl_;
  ContactPlanResult result;
  if (std::optional<std::string> problem = m.PathProblem(samples)) {
    result.status = ContactPlanStatus::kInvalidInput;
    result.reason = std::move(*problem);
    return result;
  }
  m.BeginQuery(samples);
  const PathPose start = m.path->At(m.path->Begin());
  const StandingResult stance = StandingAt(m.ctx(), start.p, start.yaw);
  if (!stance.state) {
    const bool timed_out = stance.failure->kind == StandingFailure::Kind::kTimeBudget;
    result.status = timed_out ? ContactPlanStatus::kTimeout : ContactPlanStatus::kNoStartStance;
    result.reason = timed_out ? "time budget of " + FixedNumber(m.config.time_budget_s, 2) + " s exhausted in the start stance"
                              : "start stance: " + stance.failure->Describe();
    result.failure_time_s = m.path->Begin();
    result.planning_time_s = m.budget.Elapsed();
    result.stats = m.stats;
    return result;
  }
  if (const auto unreachable = m.GoalUnreachableResult(stance.state->feet)) return *unreachable;
  Node root;
  root.state = *stance.state;
  root.t = m.path->Begin();
  return m.SearchFrom(root, -1);
}

ContactPlanResult ContactPlanner::PlanHorizon(const WholeBodyState& current,
                                              const std::vector<RootPathSample>& remaining_path, int max_steps) {
  Impl& m = *impl_;
  ContactPlanResult result;
  std::optional<std::string> problem = m.PathProblem(remaining_path);
  if (!problem && max_steps < 1) problem = "max_steps must be at least 1";
  if (!problem && (!current.base_position.allFinite() || !current.base_rpy.allFinite())) {
    problem = "current state: base pose is not finite";
  }
  if (!problem && !(current.moving_leg >= -1 && current.moving_leg < kNumLegs)) {
    problem = "current state: moving_leg must be -1 or a leg index, got " + std::to_string(current.moving_leg);
  }
  if (problem) {
    result.status = ContactPlanStatus::kInvalidInput;
    result.reason = std::move(*problem);
    return result;
  }
  m.BeginQuery(remaining_path);
  Node root;
  root.state = current;  // its moving_leg (the leg that stepped last) continues the crawl
  root.t = m.path->Begin();
  if (current.moving_leg >= 0) {
    // That step was taken at about this path time: the leg steps again only once the trunk has
    // advanced, as within one search (a horizon that re-placed it again would undo its step).
    root.steps_at_time = 1;
    root.stepped_at_time[static_cast<std::size_t>(current.moving_leg)] = true;
  }
  const Eigen::Isometry3d base = BasePose(current);
  const std::optional<JointVector> joints = SolveStance(m.ctx(), base, current.feet, kNoMargins);
  if (!joints) {
    result.status = ContactPlanStatus::kInvalidInput;
    result.reason = "current state: a foot is out of kinematic reach at the current base pose";
    result.planning_time_s = m.budget.Elapsed();
    return result;
  }
  root.state.joints = *joints;
  if (const auto unreachable = m.GoalUnreachableResult(current.feet)) return *unreachable;
  const PathPose start = m.path->At(root.t);
  root.shift = Yaw(start.yaw).transpose() * (current.base_position - start.p);
  if (m.config.base_pose.follow_feet) root.shift.z() = 0.0;  // the height follows the feet
  ContactPlanResult result_from = m.SearchFrom(root, max_steps);
  if (result_from.status == ContactPlanStatus::kNoFoothold && root.steps_at_time > 0) {
    // Only re-placing that leg at once frees the others (it blocks a lift-off): search again
    // with the leg free to step.
    root.steps_at_time = 0;
    root.stepped_at_time.fill(false);
    ContactPlanResult again = m.SearchFrom(root, max_steps);
    if (again.ok) result_from = std::move(again);
  }
  if (!result_from.plan.states.empty()) result_from.plan.states.front().MarkAsStart();
  return result_from;
}

namespace {

StanceResult StanceFailure(ContactPlanStatus status, std::string reason) {
  StanceResult result;
  result.status = status;
  result.reason = std::move(reason);
  return result;
}

StanceResult StanceFound(WholeBodyState state) {
  StanceResult result;
  result.status = ContactPlanStatus::kOk;
  result.state = std::move(state);
  return result;
}

}  // namespace

void ContactPlanner::TimeWalk(ContactPlan* plan, ContactPlanStats* stats, int keep_steps) const {
  RBCP_CHECK(plan != nullptr, "a plan to time");
  TimeWalkOf(impl_->ctx().stance, plan, stats, keep_steps);
}

StanceResult ContactPlanner::StandingStance(const Eigen::Vector3d& base_position_W, double yaw) {
  impl_->budget.Start(impl_->config.time_budget_s);
  if (!impl_->context) return StanceFailure(ContactPlanStatus::kInvalidInput, "no terrain set");
  StandingResult stance = StandingAt(impl_->ctx(), base_position_W, yaw);
  if (stance.state) return StanceFound(std::move(*stance.state));
  const bool out_of_time = stance.failure->kind == StandingFailure::Kind::kTimeBudget;
  return StanceFailure(out_of_time ? ContactPlanStatus::kTimeout : ContactPlanStatus::kNoStartStance,
                       stance.failure->Describe());
}

StanceResult ContactPlanner::MeasuredStance(const Eigen::Vector3d& base_position_W, const Eigen::Vector3d& base_rpy,
                                            const std::array<Eigen::Vector3d, kNumLegs>& feet_W,
                                            double max_offset_m) const {
  if (!impl_->context) return StanceFailure(ContactPlanStatus::kInvalidInput, "no terrain set");
  if (!base_position_W.allFinite() || !base_rpy.allFinite()) {
    return StanceFailure(ContactPlanStatus::kInvalidInput, "the base pose is not finite");
  }
  WholeBodyState state;
  state.base_position = base_position_W;
  state.base_rpy = base_rpy;
  for (Leg leg : kAllLegs) {
    const std::size_t i = static_cast<std::size_t>(Index(leg));
    const Eigen::Vector3d& p = feet_W[i];
    if (!p.allFinite()) {
      return StanceFailure(ContactPlanStatus::kInvalidInput, std::string(LegName(leg)) + " foot position is not finite");
    }
    double best = std::numeric_limits<double>::infinity();
    for (const ConvexPolygon3d& surface : impl_->surfaces) {
      const Eigen::Vector3d c = surface.ClosestPoint(p);
      const double d = (c - p).norm();
      if (d < best) {
        best = d;
        state.feet[i].position = c;
        state.feet[i].normal = surface.Normal();
      }
    }
    if (!(best <= max_offset_m)) {
      return StanceFailure(ContactPlanStatus::kNoStartStance,
                           std::string(LegName(leg)) + " foot at (" + FixedNumber(p.x()) + ", " + FixedNumber(p.y()) +
                               ", " + FixedNumber(p.z()) + ") is " + FixedNumber(best) +
                               " m from the nearest contact surface (at most " + FixedNumber(max_offset_m) + " m)");
    }
  }
  return StanceFound(std::move(state));
}

namespace {

/// Why `plan` cannot be merged: a state with a non-finite number, or states not one step apart;
/// nullopt when it can.
std::optional<std::string> MergeProblem(const ContactPlan& plan) {
  for (std::size_t i = 0; i < plan.states.size(); ++i) {
    const WholeBodyState& s = plan.states[i];
    bool finite = s.base_position.allFinite() && s.base_rpy.allFinite() && s.joints.allFinite();
    for (const FootContact& foot : s.feet) finite = finite && foot.position.allFinite() && foot.normal.allFinite();
    if (!finite) return "ContactPlanner::MergeSteps: state " + std::to_string(i) + " is not finite";
  }
  for (std::size_t i = 1; i < plan.states.size(); ++i) {
    const int leg = plan.states[i].moving_leg;
    if (leg < 0 || leg >= kNumLegs) {
      return "ContactPlanner::MergeSteps: state " + std::to_string(i) + " has no moving leg";
    }
    for (int other = 0; other < kNumLegs; ++other) {
      const std::size_t o = static_cast<std::size_t>(other);
      if (other != leg && (plan.states[i].feet[o].position - plan.states[i - 1].feet[o].position).norm() > 1e-9) {
        return "ContactPlanner::MergeSteps: state " + std::to_string(i) + " moves " +
               std::string(LegName(kAllLegs[o])) + ", not only its moving leg";
      }
    }
  }
  return std::nullopt;
}

}  // namespace

ContactPlanResult ContactPlanner::MergeSteps(const ContactPlan& plan) {
  ContactPlanResult result;
  std::optional<std::string> problem =
      impl_->context ? MergeProblem(plan) : std::optional<std::string>("ContactPlanner::MergeSteps: no terrain set");
  if (problem) {
    result.status = ContactPlanStatus::kInvalidInput;
    result.reason = std::move(*problem);
    return result;
  }
  impl_->budget.Start(impl_->config.time_budget_s);
  result.plan = plan;
  result.plan.states = contact_planner_detail::MergeSteps(impl_->ctx(), plan.states, &result.stats.steps_merged);
  contact_planner_detail::AttachSwings(impl_->ctx(), result.plan.states);
  TimeWalkOf(impl_->ctx().stance, &result.plan, &result.stats);
  result.ok = true;
  result.status = ContactPlanStatus::kOk;
  result.steps = static_cast<int>(result.plan.states.size()) - 1;
  result.reached_goal = plan.reaches_goal;
  result.planning_time_s = impl_->budget.Elapsed();
  return result;
}

namespace {

/// `plan` with its states replaced by `states`, checked again by FromStart or OnThisTerrain
/// (nullopt: a state is not valid; `why` says so), swings attached again and the walk timed with
/// every step's duration kept, which may fail its check at no more steps than plan's did.
ContactPlanResult WithRevalidatedStates(const PlannerContext& ctx, const ContactPlan& plan,
                                        std::optional<std::vector<WholeBodyState>> states, const std::string& where,
                                        const std::string& why) {
  ContactPlanResult result;
  result.status = ContactPlanStatus::kNoFoothold;
  if (!states) {
    result.reason = where + " " + why;
    return result;
  }
  const int steps = static_cast<int>(plan.states.size()) - 1;
  ContactPlan before = plan;
  result.plan = plan;
  result.plan.states = std::move(*states);
  contact_planner_detail::AttachSwings(ctx, result.plan.states);
  const int keep = plan.Timed() ? steps : 0;
  const std::vector<DynamicStepCheck> checks_before = TimeWalkOf(ctx.stance, &before, nullptr, keep);
  const std::vector<DynamicStepCheck> checks = TimeWalkOf(ctx.stance, &result.plan, &result.stats, keep);
  if (WalkFailures(checks) > WalkFailures(checks_before)) {
    result.reason = where + " the plan's dynamic walk fails its check at more steps";
    return result;
  }
  result.ok = true;
  result.status = ContactPlanStatus::kOk;
  result.steps = steps;
  result.reached_goal = plan.reaches_goal;
  return result;
}

ContactPlanResult NoTerrainOrState(const char* what, bool has_terrain) {
  ContactPlanResult result;
  result.status = ContactPlanStatus::kInvalidInput;
  result.reason = std::string("ContactPlanner::") + what + (has_terrain ? ": no state" : ": no terrain set");
  return result;
}

}  // namespace

ContactPlanResult ContactPlanner::FromStart(const ContactPlan& plan, const WholeBodyState& start) {
  if (!impl_->context || plan.states.empty()) return NoTerrainOrState("FromStart", impl_->context.has_value());
  impl_->budget.Start(impl_->config.time_budget_s);
  const PlannerContext& ctx = impl_->ctx();
  ContactPlanResult result = WithRevalidatedStates(
      ctx, plan, contact_planner_detail::FromStart(ctx, plan.states, start), "from this stance",
      "a state of the plan is not valid (checked as step merging checks a state it changes), or the stance differs "
      "in more than one foot");
  result.planning_time_s = impl_->budget.Elapsed();
  return result;
}

ContactPlanResult ContactPlanner::OnThisTerrain(const ContactPlan& plan, double max_offset_m) {
  if (!impl_->context || plan.states.empty()) return NoTerrainOrState("OnThisTerrain", impl_->context.has_value());
  impl_->budget.Start(impl_->config.time_budget_s);
  const PlannerContext& ctx = impl_->ctx();
  ContactPlanResult result = WithRevalidatedStates(
      ctx, plan, contact_planner_detail::OnTerrain(ctx, plan.states, max_offset_m), "on this terrain",
      "a foothold of the plan has no contact surface within " + FixedNumber(max_offset_m) +
          " m, or a state is not valid");
  result.planning_time_s = impl_->budget.Elapsed();
  return result;
}

const ContactPlannerConfig& ContactPlanner::Config() const { return impl_->config; }
const EquilibriumConfig& ContactPlanner::EquilibriumParameters() const { return impl_->eq_config; }

}  // namespace rbcp
