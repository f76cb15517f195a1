#include "rbcp/contact_planner/contact_planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <string_view>
#include <tuple>
#include <unordered_set>

#include "rbcp/affordance/surface_graph.h"
#include "rbcp/collision/robot_terrain_collision.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/equilibrium/stance_torques.h"
#include "rbcp/equilibrium/static_equilibrium.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/robot/robot_model.h"
#include "crawl_order.h"
#include "foothold_query.h"
#include "path_track.h"
#include "planner_context.h"
#include "search_node.h"
#include "stance_checks.h"
#include "step.h"
#include "surface_geometry.h"

namespace rbcp {

using contact_planner_detail::BaseVariant;
using contact_planner_detail::Candidate;
using contact_planner_detail::ClosestPointInTriangle;
using contact_planner_detail::CrawlNext;
using contact_planner_detail::Contacts;
using contact_planner_detail::FeetPositions;
using contact_planner_detail::KeepFailure;
using contact_planner_detail::KeepLeg;
using contact_planner_detail::kNoMargins;
using contact_planner_detail::kTieOrder;
using contact_planner_detail::LegKeep;
using contact_planner_detail::LiftOffCollision;
using contact_planner_detail::Node;
using contact_planner_detail::NumVariants;
using contact_planner_detail::PlannerContext;
using contact_planner_detail::RankedCandidates;
using contact_planner_detail::SolveStance;
using contact_planner_detail::StanceBase;
using contact_planner_detail::StanceBaseAt;
using contact_planner_detail::StepAttempt;
using contact_planner_detail::StepOutcome;
using contact_planner_detail::TieRank;
using contact_planner_detail::TimeBudget;
using contact_planner_detail::TorqueProblem;
using contact_planner_detail::TransitProblem;
using contact_planner_detail::TryStep;
using contact_planner_detail::WorkspaceRatio;
using contact_planner_detail::ConvexPolygon3d;
using contact_planner_detail::ErodeTriangle;
using contact_planner_detail::FarEnoughFromFeet;
using contact_planner_detail::LeadPose;
using contact_planner_detail::PathBasePose;
using contact_planner_detail::PathPose;
using contact_planner_detail::PathTrack;
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

Eigen::Isometry3d BasePose(const WholeBodyState& state) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = RotationFromRpy(state.base_rpy);
  T.translation() = state.base_position;
  return T;
}

namespace {

/// Interpolation step of a RootPath handed to Plan() [s].
constexpr double kRootPathSampling = 0.01;
/// Two footholds of one leg closer than this are the same step when searching [m].
constexpr double kSameFoothold = 0.01;
struct LegRank {
  Leg leg;
  double stretch;  ///< largest workspace ratio (> 1 outside)
  bool failing;
};

struct KeepResult {
  bool reached_end = false;
  double t_good = 0.0;
  std::vector<LegRank> ranking;  ///< failing legs first, by stretch
  std::string why;               ///< what failed first
};

}  // namespace

struct ContactPlanner::Impl {
  const RobotModel& robot;
  const LimbDatabase& db;
  EquilibriumConfig eq_config;
  ContactPlannerConfig config;
  StaticEquilibrium equilibrium;
  double torque_limit;
  std::unique_ptr<RobotTerrainCollision> collision;       // terrain checks, thighs with their clearance
  std::unique_ptr<RobotTerrainCollision> self_collision;  // self-collision, exact shapes
  std::vector<ConvexPolygon3d> surfaces;
  std::unique_ptr<SurfaceGraph> surface_graph;
  std::optional<PlannerContext> context;  // set with the terrain

  // Per query.
  TimeBudget budget;
  ContactPlanStats stats;
  std::optional<PathTrack> path;
  // Crawl timing of the current search (gait_advance_s, or one of its retry values).
  double gait_advance = 0.0;
  // The most informative failure seen (deepest along the path).
  double fail_t = -1.0;
  int fail_leg = -1;
  std::string fail_why;

  Impl(const RobotModel& r, const LimbDatabase& d, const EquilibriumConfig& e, const ContactPlannerConfig& c)
      : robot(r),
        db(d),
        eq_config(e),
        config(c),
        equilibrium(r.TotalMass(), e),
        torque_limit(c.torque_limit_fraction * r.ContinuousTorqueLimit()) {
    config.Validate();
  }

  const PlannerContext& ctx() const { return *context; }

  void SetTerrainContext() {
    context.emplace(PlannerContext{robot, db, eq_config, config, torque_limit, *collision, *self_collision, surfaces,
                                   equilibrium, stats, budget});
  }

  void ResetFailure() {
    fail_t = -1.0;
    fail_leg = -1;
    fail_why.clear();
  }

  void NoteFailure(double t, Leg leg, const std::string& why) {
    if (t >= fail_t) {
      fail_t = t;
      fail_leg = Index(leg);
      fail_why = why;
    }
  }

  // ---- Keep phase ------------------------------------------------------------------------------

  /// Tests the node's four feet at path time t. Fills per-leg failure flags and stretches.
  bool KeepAt(const Node& node, double t, std::array<bool, kNumLegs>* failing, std::array<double, kNumLegs>* stretch,
              std::string* why) {
    const Eigen::Isometry3d base = StanceBaseAt(ctx(), path->At(t), node.shift, node.state.feet).base_W;
    JointVector q = JointVector::Zero();
    bool all_ok = true;
    for (Leg leg : kAllLegs) {
      const std::size_t i = static_cast<std::size_t>(Index(leg));
      const LegKeep keep = KeepLeg(ctx(), leg, base, node.state.feet[i].position);
      (*stretch)[i] = keep.stretch;
      const KeepFailure f = keep.failure;
      (*failing)[i] = f != KeepFailure::kNone;
      if (f != KeepFailure::kNone) {
        all_ok = false;
        if (why && why->empty()) {
          *why = std::string(LegName(leg)) +
                 (f == KeepFailure::kWorkspace    ? " leaves its workspace"
                  : f == KeepFailure::kKinematics ? " out of kinematic reach"
                                                  : " in collision");
        }
      } else {
        SetLegJoints(q, leg, keep.q);
      }
    }
    if (!all_ok) return false;
    bool body_ok = !collision->CheckTrunk(base).collision;
    if (body_ok) {
      const double margin = SupportPolygonMargin(FeetPositions(node.state.feet, -1), CoM(ctx(), base, q));
      body_ok = margin >= eq_config.support_margin_m;
    }
    if (!body_ok) {
      // Not attributable to one leg: every leg may step, the most stretched first.
      failing->fill(true);
      if (why && why->empty()) *why = "trunk collision or CoM near the edge of the support polygon";
      return false;
    }
    return true;
  }

  KeepResult KeepPhase(const Node& node) {
    KeepResult result;
    std::array<bool, kNumLegs> failing{};
    std::array<double, kNumLegs> stretch{};
    const double end = path->End();
    auto finish = [&](double t_good, const std::array<bool, kNumLegs>& fail, const std::array<double, kNumLegs>& str) {
      result.t_good = t_good;
      for (Leg leg : kAllLegs) {
        const std::size_t i = static_cast<std::size_t>(Index(leg));
        result.ranking.push_back({leg, str[i], fail[i]});
      }
      std::sort(result.ranking.begin(), result.ranking.end(), [](const LegRank& a, const LegRank& b) {
        if (a.failing != b.failing) return a.failing;
        if (std::abs(a.stretch - b.stretch) > 1e-6) return a.stretch > b.stretch;
        return TieRank(a.leg) < TieRank(b.leg);
      });
    };
    std::string why;
    if (!KeepAt(node, node.t, &failing, &stretch, &why)) {
      result.why = why;
      finish(node.t, failing, stretch);
      return result;
    }
    double t_ok = node.t;
    std::array<double, kNumLegs> ok_stretch = stretch;
    while (t_ok < end) {
      const double t = std::min(end, t_ok + config.path_step_s);
      why.clear();
      if (KeepAt(node, t, &failing, &stretch, &why)) {
        t_ok = t;
        ok_stretch = stretch;
        continue;
      }
      // Bisect to the last keepable time.
      double lo = t_ok, hi = t;
      std::array<bool, kNumLegs> hi_failing = failing;
      std::array<double, kNumLegs> hi_stretch = stretch;
      std::string hi_why = why;
      while (hi - lo > config.step_time_resolution_s) {
        const double mid = 0.5 * (lo + hi);
        std::string w;
        if (KeepAt(node, mid, &failing, &stretch, &w)) {
          lo = mid;
        } else {
          hi = mid;
          hi_failing = failing;
          hi_stretch = stretch;
          hi_why = w;
        }
      }
      result.why = hi_why;
      finish(lo, hi_failing, hi_stretch);
      return result;
    }
    result.reached_end = true;
    finish(end, std::array<bool, kNumLegs>{}, ok_stretch);
    return result;
  }

  // ---- Reachability of the goal ---------------------------------------------------------------

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

  // ---- Start stance ----------------------------------------------------------------------------

  std::optional<WholeBodyState> Standing(const Eigen::Vector3d& base_position, double yaw, std::string* reason) {
    auto fail = [&](const std::string& why) -> std::optional<WholeBodyState> {
      if (reason) *reason = why;
      return std::nullopt;
    };
    if (!collision) return fail("no terrain set");
    const PathPose pose{base_position, yaw};
    const Eigen::Isometry3d base = PathBasePose(pose);
    WholeBodyState state;
    state.base_position = base_position;
    state.base_rpy = Eigen::Vector3d(0.0, 0.0, yaw);
    state.moving_leg = -1;
    JointVector q = JointVector::Zero();
    std::array<bool, kNumLegs> placed{};
    for (Leg leg : kTieOrder) {
      const std::size_t i = static_cast<std::size_t>(Index(leg));
      const Eigen::Vector3d target = base * robot.ReferenceFootPosition(leg);
      const std::vector<Candidate> cands = RankedCandidates(ctx(), leg, base, target, yaw);
      bool found = false;
      for (const Candidate& c : cands) {
        ++stats.candidates_evaluated;
        bool separated = true;
        for (int k = 0; k < kNumLegs; ++k) {
          if (placed[static_cast<std::size_t>(k)] &&
              (state.feet[static_cast<std::size_t>(k)].position - c.foothold).head<2>().norm() <
                  config.foothold.min_foot_separation_m) {
            separated = false;
          }
        }
        if (!separated) continue;
        const LegKeep keep = KeepLeg(ctx(), leg, base, c.foothold);
        if (keep.failure != KeepFailure::kNone) continue;
        state.feet[i].position = c.foothold;
        state.feet[i].normal = surfaces[static_cast<std::size_t>(c.surface)].Normal();
        SetLegJoints(q, leg, keep.q);
        placed[i] = true;
        found = true;
        break;
      }
      if (!found) {
        return fail(std::string("no valid foothold for ") + std::string(LegName(leg)) + " near its reference position (" +
                    std::to_string(cands.size()) + " candidates)");
      }
    }
    state.joints = q;
    if (collision->CheckTrunk(base).collision) return fail("trunk collides with the terrain");
    const CollisionReport self = self_collision->CheckSelf(q);
    if (self.collision) return fail("self-collision " + self.first_shape + " / " + self.obstacle);
    const Eigen::Vector3d com = CoM(ctx(), base, q);
    ++stats.stability_evaluations;
    const EquilibriumResult eq = equilibrium.Robustness(Contacts(state.feet, -1), com);
    if (!equilibrium.MeetsThreshold(eq)) {
      return fail("standing stance not statically stable (robustness " + FixedNumber(eq.robustness_N, 2) + " N)");
    }
    const double margin = SupportPolygonMargin(FeetPositions(state.feet, -1), com);
    if (margin < eq_config.support_margin_m) return fail("CoM " + FixedNumber(margin) + " m inside the support polygon");
    const std::string torque = TorqueProblem(ctx(), base, q, state.feet, -1, com);
    if (!torque.empty()) return fail("standing stance: " + torque);
    return state;
  }

  // ---- Search ----------------------------------------------------------------------------------

  double GoalDistance(const Node& node, Leg leg) const {
    const Eigen::Vector3d goal =
        PathBasePose(path->At(path->End())) * robot.ReferenceFootPosition(leg);
    return (node.state.feet[static_cast<std::size_t>(Index(leg))].position - goal).head<2>().norm();
  }

  static long TimeKey(double t) { return std::lround(t * 1e6); }

  void Expand(Node& node) {
    node.expanded = true;
    const double end = path->End();
    const int n_leads = static_cast<int>(config.foothold.lead_time_factors.size());
    auto allowed = [&](Leg leg, double t) {
      const bool same_time = t <= node.t + 1e-9;
      if (!same_time) return true;
      if (node.steps_at_time >= config.retry.max_steps_at_one_time) return false;
      return !node.stepped_at_time[static_cast<std::size_t>(Index(leg))];
    };
    if (node.t >= end - 1e-9) {
      // At the path end: re-place the feet far from their goal positions.
      std::vector<std::pair<double, Leg>> far;
      for (Leg leg : kAllLegs) far.push_back({GoalDistance(node, leg), leg});
      std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) {
        if (a.first != b.first) return a.first > b.first;
        return TieRank(a.second) < TieRank(b.second);
      });
      if (far.front().first <= config.goal_foot_tolerance_m) {
        node.goal = true;
        return;
      }
      for (const auto& [d, leg] : far) {
        if (allowed(leg, end)) node.options.push_back({leg, end, 0, true, 0});
      }
      return;
    }
    const KeepResult keep = KeepPhase(node);
    if (keep.reached_end) {
      // The trunk reaches the path end with these feet: the remaining steps happen there.
      std::vector<std::pair<double, Leg>> far;
      for (Leg leg : kAllLegs) far.push_back({GoalDistance(node, leg), leg});
      std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) {
        if (a.first != b.first) return a.first > b.first;
        return TieRank(a.second) < TieRank(b.second);
      });
      for (const auto& [d, leg] : far) node.options.push_back({leg, end, 0, true, 0});
      return;
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
    // Crawl timing: the next leg in the crawl order steps after at most gait_advance_s of path
    // time, from the parent's shift first, then from the path pose, with other leads and shift
    // starts.
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
      if (allowed(gait_leg, t_gait)) add_every_variant(gait_leg, t_gait);
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
    if (!keep.ranking.empty() && keep.ranking.front().failing) {
      NoteFailure(keep.t_good, keep.ranking.front().leg, keep.why);
    }
  }

  ContactPlanResult Search(Node root, int max_steps) {
    ContactPlanResult result;
    std::vector<Node> stack;
    stack.push_back(std::move(root));
    int backtracks = 0;
    auto finish_fail = [&](ContactPlanStatus status, const std::string& reason) {
      result.ok = false;
      result.status = status;
      result.reason = reason;
      result.failure_time_s = fail_t;
      result.failure_leg = fail_leg;
      return result;
    };
    auto describe_failure = [&]() {
      std::string r;
      if (fail_leg >= 0) {
        r = std::string("no valid step for ") + std::string(LegName(kAllLegs[static_cast<std::size_t>(fail_leg)])) +
            " at path time " + FixedNumber(fail_t, 2) + " s";
        if (!fail_why.empty()) r += ": " + fail_why;
      } else {
        r = "no valid step: " + fail_why;
      }
      return r;
    };
    while (true) {
      if (budget.Exhausted()) {
        return finish_fail(ContactPlanStatus::kTimeout, "time budget of " + FixedNumber(config.time_budget_s, 2) +
                                                            " s exhausted; furthest failure: " + describe_failure());
      }
      Node& node = stack.back();
      const int steps = static_cast<int>(stack.size()) - 1;
      if (!node.expanded) {
        if (max_steps >= 0 && steps >= max_steps) {
          node.expanded = true;
          node.goal = true;
          result.reached_goal = false;
        } else {
          Expand(node);
          if (node.goal) result.reached_goal = true;
        }
      }
      if (node.goal) break;
      if (node.next_option < node.options.size() &&
          static_cast<int>(node.children.size()) < config.retry.max_children_per_state) {
        const Node::Option option = node.options[node.next_option++];
        const std::tuple<int, long, int> key{Index(option.leg), TimeKey(option.t), option.variant};
        if (node.exhausted.count(key)) continue;
        StepAttempt attempt = TryStep(ctx(), *path, node, option);
        if (attempt.blocking) {
          // A stance leg hits the terrain (a riser, a wall) when the body shifts for this swing,
          // or narrows the swing's support triangle: re-place that leg first, at the same time,
          // before the remaining options.
          const Leg blocker = *attempt.blocking;
          const bool same_time = option.t <= node.t + 1e-9;
          const bool allowed = !same_time || (node.steps_at_time < config.retry.max_steps_at_one_time &&
                                              !node.stepped_at_time[static_cast<std::size_t>(Index(blocker))]);
          if (allowed && node.repositions.insert({Index(blocker), TimeKey(option.t)}).second) {
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
          continue;
        }
        if (attempt.outcome == StepOutcome::kNoCandidate || attempt.outcome == StepOutcome::kPoseInvalid) {
          node.exhausted.insert(key);
        }
        NoteFailure(option.t, option.leg, attempt.why);
        continue;
      }
      // Every option failed: undo this node's step.
      if (stack.size() == 1 || backtracks >= config.retry.max_backtracks) {
        return finish_fail(ContactPlanStatus::kNoFoothold,
                           describe_failure() + (stack.size() == 1 ? "" : " (backtracking limit reached)"));
      }
      stack.pop_back();
      ++backtracks;
      ++stats.backtracks;
    }
    result.ok = true;
    result.status = ContactPlanStatus::kOk;
    for (const Node& n : stack) result.plan.states.push_back(n.state);
    result.steps = static_cast<int>(result.plan.states.size()) - 1;
    return result;
  }

  /// Search() with gait_advance_s; when that fails for want of footholds (not time), again from
  /// the same root with each of retry.gait_advance_s in turn while time remains. The crawl timing
  /// decides where every foot stands when the terrain gets hard, so a dead end under one timing is
  /// rarely one under another.
  ContactPlanResult SearchWithRetries(const Node& root, int max_steps) {
    ContactPlanResult first = Search(root, max_steps);
    if (first.ok || first.status != ContactPlanStatus::kNoFoothold) return first;
    std::string tried;
    for (const double advance : config.retry.gait_advance_s) {
      if (budget.Exhausted()) {
        // The wall clock is a safety limit: the answer must not depend on how far it let us get.
        first.status = ContactPlanStatus::kTimeout;
        first.reason = "time budget of " + FixedNumber(config.time_budget_s, 2) +
                       " s exhausted before the retry with gait_advance_s " + FixedNumber(advance, 2) +
                       " s; first search: " + first.reason;
        return first;
      }
      gait_advance = advance;
      ResetFailure();
      ContactPlanResult again = Search(root, max_steps);
      if (again.ok || again.status != ContactPlanStatus::kNoFoothold) return again;
      tried += (tried.empty() ? "" : ", ") + FixedNumber(advance, 2);
    }
    if (!tried.empty()) first.reason += " (also with gait_advance_s " + tried + " s)";
    return first;
  }

  void BeginQuery(std::vector<RootPathSample> samples) {
    budget.Start(config.time_budget_s);
    stats = ContactPlanStats{};
    ResetFailure();
    gait_advance = config.gait_advance_s;
    path.emplace(std::move(samples), config.path_yaw_smoothing_s);
  }

  std::string CheckPath(const std::vector<RootPathSample>& samples) const {
    if (samples.empty()) return "the root path has no sample";
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (!samples[i].p.allFinite() || !std::isfinite(samples[i].yaw) || !std::isfinite(samples[i].t)) {
        return "root path sample " + std::to_string(i) + " is not finite";
      }
      if (i > 0 && !(samples[i].t > samples[i - 1].t)) {
        return "root path times must increase (sample " + std::to_string(i) + ")";
      }
    }
    if (!collision) return "no terrain set";
    return "";
  }
};

ContactPlanner::ContactPlanner(const RobotModel& robot, const LimbDatabase& database,
                               const EquilibriumConfig& equilibrium, const ContactPlannerConfig& config)
    : impl_(std::make_unique<Impl>(robot, database, equilibrium, config)) {}
ContactPlanner::~ContactPlanner() = default;
ContactPlanner::ContactPlanner(ContactPlanner&&) noexcept = default;
ContactPlanner& ContactPlanner::operator=(ContactPlanner&&) noexcept = default;

void ContactPlanner::SetTerrain(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces) {
  CollisionOptions terrain_options;
  terrain_options.thigh_margin = impl_->config.thigh_clearance_m;
  impl_->collision = std::make_unique<RobotTerrainCollision>(impl_->robot, terrain, terrain_options);
  impl_->self_collision = std::make_unique<RobotTerrainCollision>(impl_->robot, terrain);
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
  const std::string problem = m.CheckPath(samples);
  if (!problem.empty()) {
    result.status = ContactPlanStatus::kInvalidInput;
    result.reason = problem;
    return result;
  }
  m.BeginQuery(samples);
  std::string why;
  const PathPose start = m.path->At(m.path->Begin());
  std::optional<WholeBodyState> stance = m.Standing(start.p, start.yaw, &why);
  if (!stance) {
    result.status = ContactPlanStatus::kNoStartStance;
    result.reason = "start stance: " + why;
    result.failure_time_s = m.path->Begin();
    result.planning_time_s = m.budget.Elapsed();
    result.stats = m.stats;
    return result;
  }
  if (const auto unreachable = m.GoalUnreachableResult(stance->feet)) return *unreachable;
  Node root;
  root.state = *stance;
  root.t = m.path->Begin();
  result = m.SearchWithRetries(root, -1);
  result.planning_time_s = m.budget.Elapsed();
  result.stats = m.stats;
  return result;
}

ContactPlanResult ContactPlanner::PlanHorizon(const WholeBodyState& current,
                                              const std::vector<RootPathSample>& remaining_path, int max_steps) {
  Impl& m = *impl_;
  ContactPlanResult result;
  std::string problem = m.CheckPath(remaining_path);
  if (problem.empty() && max_steps < 1) problem = "max_steps must be at least 1";
  if (problem.empty() && (!current.base_position.allFinite() || !current.base_rpy.allFinite())) {
    problem = "current state: base pose is not finite";
  }
  if (!problem.empty()) {
    result.status = ContactPlanStatus::kInvalidInput;
    result.reason = problem;
    return result;
  }
  m.BeginQuery(remaining_path);
  Node root;
  root.state = current;
  root.state.moving_leg = -1;
  root.t = m.path->Begin();
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
  result = m.SearchWithRetries(root, max_steps);
  result.planning_time_s = m.budget.Elapsed();
  result.stats = m.stats;
  return result;
}

std::optional<WholeBodyState> ContactPlanner::StandingStance(const Eigen::Vector3d& base_position_W, double yaw,
                                                             std::string* reason) {
  impl_->budget.Start(impl_->config.time_budget_s);
  return impl_->Standing(base_position_W, yaw, reason);
}

const ContactPlannerConfig& ContactPlanner::Config() const { return impl_->config; }
const EquilibriumConfig& ContactPlanner::EquilibriumParameters() const { return impl_->eq_config; }

}  // namespace rbcp
