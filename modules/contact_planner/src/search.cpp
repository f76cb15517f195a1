#include "search.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "crawl_order.h"
#include "keep_phase.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/robot/robot_model.h"
#include "step.h"

namespace rbcp::contact_planner_detail {
namespace {

/// Two footholds of one leg closer than this are the same step when searching [m].
constexpr double kSameFoothold = 0.01;

long TimeKey(double t) { return std::lround(t * 1e6); }

/// Whether `leg` may step from `node` at path time t: always once the trunk has advanced;
/// without it, at most retry.max_steps_at_one_time steps and each leg once.
bool MayStep(const ContactPlannerConfig& config, const Node& node, Leg leg, double t) {
  const bool same_time = t <= node.t + 1e-9;
  if (!same_time) return true;
  if (node.steps_at_time >= config.retry.max_steps_at_one_time) return false;
  return !node.stepped_at_time[static_cast<std::size_t>(Index(leg))];
}

/// The legs with the horizontal distance of their foot from its reference position at the path
/// end, farthest first (ties in kTieOrder).
std::vector<std::pair<double, Leg>> LegsByGoalDistance(const PlannerContext& ctx, const PathTrack& path,
                                                       const Node& node) {
  const Eigen::Isometry3d end = PathBasePose(path.At(path.End()));
  std::vector<std::pair<double, Leg>> far;
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d goal = end * ctx.robot.ReferenceFootPosition(leg);
    far.push_back({(node.state.feet[static_cast<std::size_t>(Index(leg))].position - goal).head<2>().norm(), leg});
  }
  std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) {
    if (a.first != b.first) return a.first > b.first;
    return TieRank(a.second) < TieRank(b.second);
  });
  return far;
}

/// Fills the node's options (or marks it the goal) and marks it expanded. At the path end the
/// feet far from their goal positions are re-placed; elsewhere the keep phase decides when and
/// which legs step. Returns the keep phase's failure, when a leg must step.
std::optional<Failure> Expand(const PlannerContext& ctx, const PathTrack& path, double gait_advance, Node& node) {
  const ContactPlannerConfig& config = ctx.config;
  RBCP_CHECK(node.state.moving_leg >= -1 && node.state.moving_leg < kNumLegs,
             "moving leg " + std::to_string(node.state.moving_leg));
  node.expanded = true;
  const double end = path.End();
  const int n_leads = static_cast<int>(config.foothold.lead_time_factors.size());
  const auto allowed = [&](Leg leg, double t) { return MayStep(config, node, leg, t); };
  if (node.t >= end - 1e-9) {
    // At the path end: re-place the feet far from their goal positions.
    const std::vector<std::pair<double, Leg>> far = LegsByGoalDistance(ctx, path, node);
    if (far.front().first <= config.goal_foot_tolerance_m) {
      node.goal = true;
      return std::nullopt;
    }
    for (const auto& [d, leg] : far) {
      if (allowed(leg, end)) node.options.push_back({leg, end, 0, true, 0});
    }
    return std::nullopt;
  }
  const KeepResult keep = KeepPhase(ctx, path, node);
  RBCP_CHECK(keep.ranking.size() == static_cast<std::size_t>(kNumLegs), "the keep phase ranks every leg");
  if (keep.reached_end) {
    // The trunk reaches the path end with these feet: the remaining steps happen there.
    for (const auto& [d, leg] : LegsByGoalDistance(ctx, path, node)) node.options.push_back({leg, end, 0, true, 0});
    return std::nullopt;
  }
  std::vector<double> times = {keep.t_good};
  for (double back : config.retry.earlier_step_s) {
    const double t = std::max(node.t, keep.t_good - back);
    if (std::none_of(times.begin(), times.end(), [&](double x) { return std::abs(x - t) < 1e-9; })) times.push_back(t);
  }
  // Crawl prior: after a hind leg, the fore leg on the same side steps next if it must.
  std::vector<LegRank> ranking = keep.ranking;
  if (node.state.moving_leg == Index(Leg::kLH) || node.state.moving_leg == Index(Leg::kRH)) {
    const Leg fore = node.state.moving_leg == Index(Leg::kLH) ? Leg::kLF : Leg::kRF;
    std::stable_partition(ranking.begin(), ranking.end(),
                          [&](const LegRank& r) { return r.failing && r.leg == fore; });
  }
  // Crawl timing: the next leg in the crawl order steps after gait_advance_s of path time, from
  // the parent's shift first, then from the path pose, with other leads and shift starts. When a
  // foot can no longer be kept before then, the failing legs step first: the crawl's leg would
  // step at the failure time, and the failing leg right after it at the same time.
  // A leg at time t with every target lead, then from every other start of the shift search.
  const auto add_every_variant = [&](Leg leg, double t) {
    for (int lead = 0; lead < n_leads; ++lead) node.options.push_back({leg, t, lead, false, 0});
    for (int v = 1; v < NumVariants(config); ++v) {
      if ((BaseVariant(config, node, v) - BaseVariant(config, node, 0)).norm() < 1e-9) continue;  // same start
      node.options.push_back({leg, t, 0, false, v});
    }
  };
  if (gait_advance > 0.0) {
    const double t_gait = std::min(keep.t_good, node.t + gait_advance);
    const Leg gait_leg = node.state.moving_leg < 0 ? ranking.front().leg
                                                   : CrawlNext(kAllLegs[static_cast<std::size_t>(node.state.moving_leg)]);
    const bool before_failure = node.t + gait_advance < keep.t_good - 1e-9;
    const bool gait_leg_fails = std::any_of(ranking.begin(), ranking.end(),
                                            [&](const LegRank& r) { return r.failing && r.leg == gait_leg; });
    if ((before_failure || gait_leg_fails) && allowed(gait_leg, t_gait)) add_every_variant(gait_leg, t_gait);
  }
  // Failing legs at the failure time, every lead, then with the other starts of the shift
  // search; then earlier; then the other legs.
  for (const LegRank& r : ranking) {
    if (r.failing && allowed(r.leg, keep.t_good)) add_every_variant(r.leg, keep.t_good);
  }
  for (std::size_t k = 1; k < times.size(); ++k) {
    for (const LegRank& r : ranking) {
      if (r.failing && allowed(r.leg, times[k])) node.options.push_back({r.leg, times[k], 0, false, 0});
    }
  }
  for (double t : times) {
    for (const LegRank& r : ranking) {
      if (!r.failing && allowed(r.leg, t)) node.options.push_back({r.leg, t, 0, false, 0});
    }
  }
  if (keep.ranking.front().failing) {
    return Failure{keep.t_good, Index(keep.ranking.front().leg), keep.why};
  }
  return std::nullopt;
}

}  // namespace

std::string Failure::Describe() const {
  RBCP_CHECK(leg >= -1 && leg < kNumLegs, "failure leg " + std::to_string(leg));
  std::string r;
  if (leg >= 0) {
    r = std::string("no valid step for ") + std::string(LegName(kAllLegs[static_cast<std::size_t>(leg)])) +
        " at path time " + FixedNumber(t, 2) + " s";
    if (!why.empty()) r += ": " + why;
  } else {
    r = "no valid step: " + why;
  }
  return r;
}

namespace {

/// The node's state and its place in the crawl, without the search's bookkeeping.
Node Unexpanded(const Node& n) {
  Node fresh;
  fresh.state = n.state;
  fresh.t = n.t;
  fresh.shift = n.shift;
  fresh.steps_at_time = n.steps_at_time;
  fresh.stepped_at_time = n.stepped_at_time;
  return fresh;
}

bool EvaluationsSpent(const PlannerContext& ctx) { return ctx.stats.Evaluations() >= ctx.config.retry.max_evaluations; }

std::string EvaluationsReason(const PlannerContext& ctx) {
  return "search bound of " + std::to_string(ctx.config.retry.max_evaluations) + " leg evaluations spent";
}

}  // namespace

ContactPlanResult Search(const PlannerContext& ctx, const PathTrack& path, const CrawlProfile& profile, Node root,
                         int max_steps, std::vector<Node>* furthest_nodes) {
  const ContactPlannerConfig& config = ctx.config;
  ContactPlanResult result;
  std::vector<Node> stack;
  stack.push_back(std::move(root));
  if (furthest_nodes) *furthest_nodes = {Unexpanded(stack.front())};
  const long long first_evaluation = ctx.stats.Evaluations();
  int backtracks = 0;
  Failure furthest;
  auto finish_fail = [&](ContactPlanStatus status, const std::string& reason) {
    result.ok = false;
    result.status = status;
    result.reason = reason;
    result.failure_time_s = furthest.t;
    result.failure_leg = furthest.leg;
    return result;
  };
  while (true) {
    if (ctx.budget.Exhausted()) {
      return finish_fail(ContactPlanStatus::kTimeout, "time budget of " + FixedNumber(config.time_budget_s, 2) +
                                                          " s exhausted; furthest failure: " + furthest.Describe());
    }
    if (EvaluationsSpent(ctx)) {
      return finish_fail(ContactPlanStatus::kNoFoothold, EvaluationsReason(ctx) + "; furthest failure: " +
                                                             furthest.Describe());
    }
    if (ctx.stats.Evaluations() - first_evaluation >= config.retry.max_search_evaluations) {
      return finish_fail(ContactPlanStatus::kNoFoothold,
                         furthest.Describe() + " (" + std::to_string(config.retry.max_search_evaluations) +
                             " leg evaluations spent in this search)");
    }
    RBCP_CHECK(!stack.empty(), "the root is never undone");
    Node& node = stack.back();
    const int steps = static_cast<int>(stack.size()) - 1;
    if (!node.expanded) {
      if (max_steps >= 0 && steps >= max_steps) {
        node.expanded = true;
        node.goal = true;
        result.reached_goal = false;
      } else {
        if (const std::optional<Failure> keep_failure = Expand(ctx, path, profile.gait_advance_s, node)) {
          furthest.Note(*keep_failure);
        }
        if (node.goal) result.reached_goal = true;
      }
    }
    if (node.goal) break;
    if (node.next_option < node.options.size() &&
        static_cast<int>(node.children.size()) < config.retry.max_children_per_state) {
      const Node::Option option = node.options[node.next_option++];
      const std::tuple<int, long, int> key{Index(option.leg), TimeKey(option.t), option.variant};
      if (node.exhausted.count(key)) continue;
      StepAttempt attempt = TryStep(ctx, path, node, option, profile);
      if (attempt.blocking) {
        // A stance leg hits the terrain (a riser, a wall) when the body shifts for this swing,
        // or narrows the swing's support triangle: re-place that leg first, at the same time,
        // before the remaining options.
        const Leg blocker = *attempt.blocking;
        RBCP_CHECK(blocker != option.leg, "a leg does not block its own lift-off");
        if (MayStep(config, node, blocker, option.t) &&
            node.repositions.insert({Index(blocker), TimeKey(option.t)}).second) {
          node.options.insert(node.options.begin() + static_cast<std::ptrdiff_t>(node.next_option),
                              Node::Option{blocker, option.t, 0, option.goal_step, 0});
        }
      }
      if (attempt.outcome == StepOutcome::kFound) {
        Node& child = attempt.child;
        const Eigen::Vector3d& foot = child.state.feet[static_cast<std::size_t>(Index(option.leg))].position;
        const bool duplicate = std::any_of(node.children.begin(), node.children.end(), [&](const auto& c) {
          return c.leg == option.leg && std::abs(c.t - child.t) < 1e-9 && (c.foot - foot).norm() < kSameFoothold;
        });
        if (duplicate) continue;
        node.children.push_back({option.leg, child.t, foot});
        stack.push_back(std::move(child));
        if (furthest_nodes && stack.back().t > furthest_nodes->back().t + 1e-9) {
          furthest_nodes->clear();
          for (const Node& n : stack) furthest_nodes->push_back(Unexpanded(n));
        }
        continue;
      }
      if (attempt.outcome == StepOutcome::kNoCandidate || attempt.outcome == StepOutcome::kPoseInvalid) {
        node.exhausted.insert(key);
      }
      furthest.Note({option.t, Index(option.leg), std::move(attempt.why)});
      continue;
    }
    // Every option failed: undo this node's step.
    if (stack.size() == 1 || backtracks >= config.retry.max_backtracks) {
      return finish_fail(ContactPlanStatus::kNoFoothold,
                         furthest.Describe() + (stack.size() == 1 ? "" : " (backtracking limit reached)"));
    }
    stack.pop_back();
    ++backtracks;
    ++ctx.stats.backtracks;
  }
  result.ok = true;
  result.status = ContactPlanStatus::kOk;
  for (const Node& n : stack) result.plan.states.push_back(n.state);
  result.steps = static_cast<int>(result.plan.states.size()) - 1;
  return result;
}

ContactPlanResult SearchWithRetries(const PlannerContext& ctx, const PathTrack& path, const Node& root, int max_steps) {
  const ContactPlannerConfig& config = ctx.config;
  std::vector<CrawlProfile> profiles;
  std::vector<double> timings = {config.gait_advance_s};
  timings.insert(timings.end(), config.retry.gait_advance_s.begin(), config.retry.gait_advance_s.end());
  std::vector<double> fractions = {config.base_shift.keep_fraction};
  fractions.insert(fractions.end(), config.retry.keep_fraction.begin(), config.retry.keep_fraction.end());
  for (const double advance : timings) {
    for (const double fraction : fractions) profiles.push_back({advance, fraction});
  }
  const auto describe = [](const CrawlProfile& p) {
    return "gait_advance_s " + FixedNumber(p.gait_advance_s, 2) + " s, keep_fraction " + FixedNumber(p.keep_fraction, 2);
  };
  const bool restart_near_failure = config.retry.restart_back_s > 0.0;
  std::vector<Node> furthest;
  ContactPlanResult first =
      Search(ctx, path, profiles.front(), root, max_steps, restart_near_failure ? &furthest : nullptr);
  if (first.ok || first.status != ContactPlanStatus::kNoFoothold) return first;
  // The restart state: the last of the furthest search's states at least restart_back_s of path
  // time before its furthest point (none when that is the root).
  std::size_t restart = 0;
  if (restart_near_failure) {
    RBCP_CHECK(!furthest.empty(), "the furthest search holds at least the root");
    const double t_restart = furthest.back().t - config.retry.restart_back_s;
    for (std::size_t k = 0; k < furthest.size() && furthest[k].t <= t_restart + 1e-9; ++k) restart = k;
    // A piece of a receding horizon counts its steps from the root: the restarted search makes
    // the ones left, and none when the restart state already has them all.
    if (max_steps >= 0 && static_cast<int>(restart) >= max_steps) restart = 0;
  }
  std::string tried;
  for (const bool from_root : {false, true}) {
    if (!from_root && restart == 0) continue;
    const std::string where = from_root ? "" : " from path time " + FixedNumber(furthest[restart].t, 2) + " s";
    for (std::size_t k = 1; k < profiles.size(); ++k) {
      if (ctx.budget.Exhausted()) {
        // The wall clock is a safety limit: the answer must not depend on how far it let us get.
        first.status = ContactPlanStatus::kTimeout;
        first.reason = "time budget of " + FixedNumber(config.time_budget_s, 2) + " s exhausted before the retry with " +
                       describe(profiles[k]) + where + "; first search: " + first.reason;
        return first;
      }
      if (EvaluationsSpent(ctx)) break;
      const int steps_left = max_steps < 0 || from_root ? max_steps : max_steps - static_cast<int>(restart);
      ContactPlanResult again = Search(ctx, path, profiles[k], from_root ? root : furthest[restart], steps_left);
      if (again.ok && !from_root) {
        // The steps of the first search up to the restart state, then the new ones.
        std::vector<WholeBodyState> states;
        for (std::size_t i = 0; i < restart; ++i) states.push_back(furthest[i].state);
        states.insert(states.end(), again.plan.states.begin(), again.plan.states.end());
        again.plan.states = std::move(states);
        again.steps = static_cast<int>(again.plan.states.size()) - 1;
      }
      if (again.ok || again.status != ContactPlanStatus::kNoFoothold) return again;
      tried += (tried.empty() ? "" : "; ") + describe(profiles[k]) + where;
    }
  }
  if (!tried.empty()) first.reason += " (also with " + tried + ")";
  return first;
}

}  // namespace rbcp::contact_planner_detail
