#include "feet_kept.h"

#include <algorithm>
#include <cmath>

#include "crawl_order.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "stance_checks.h"

namespace rbcp::contact_planner_detail {

std::string KeepStop::Describe() const {
  switch (kind) {
    case Kind::kLeg:
      return std::string(LegName(leg)) + (leg_failure == KeepFailure::kWorkspace    ? " leaves its workspace"
                                          : leg_failure == KeepFailure::kKinematics ? " out of kinematic reach"
                                                                                    : " in collision");
    case Kind::kBody: return "trunk collision or CoM near the edge of the support polygon";
    case Kind::kTimeBudget: return "time budget exhausted";
  }
  return "unknown keep stop";
}

KeepCheck KeepAt(const PlannerContext& ctx, const PathTrack& path, const Node& node, double t) {
  KeepCheck check;
  const Eigen::Isometry3d base = StanceBaseAt(ctx, path.At(t), node.shift, node.state.feet).base_W;
  JointVector q = JointVector::Zero();
  for (Leg leg : kAllLegs) {
    const std::size_t i = static_cast<std::size_t>(Index(leg));
    const LegKeep keep = KeepLeg(ctx, leg, base, node.state.feet[i].position);
    check.stretch[i] = keep.stretch;
    check.failing[i] = keep.failure != KeepFailure::kNone;
    if (keep.failure != KeepFailure::kNone) {
      if (!check.failure) check.failure = KeepStop{KeepStop::Kind::kLeg, leg, keep.failure};
    } else {
      SetLegJoints(q, leg, keep.q);
    }
  }
  if (check.failure) return check;
  bool body_ok = !ctx.stance.TerrainCollision().CheckTrunk(base).collision;
  if (body_ok) body_ok = SupportHolds(ctx, node.state.feet, -1, CoM(ctx, base, q));
  if (!body_ok) {
    // Not attributable to one leg: every leg may step, the most stretched first.
    check.failing.fill(true);
    check.failure = KeepStop{KeepStop::Kind::kBody};
  }
  return check;
}

KeptFeetAdvance AdvanceWithFeetKept(const PlannerContext& ctx, const PathTrack& path, const Node& node) {
  KeptFeetAdvance result;
  const double end = path.End();
  auto finish = [&](double t_last_keepable, const std::array<bool, kNumLegs>& fail,
                    const std::array<double, kNumLegs>& str) {
    result.t_last_keepable = t_last_keepable;
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
  const KeepCheck first = KeepAt(ctx, path, node, node.t);
  if (!first.ok()) {
    result.stop = first.failure;
    finish(node.t, first.failing, first.stretch);
    return result;
  }
  double t_ok = node.t;
  std::array<double, kNumLegs> ok_stretch = first.stretch;
  while (t_ok < end) {
    if (ctx.budget.Exhausted()) {
      // A long path is walked in small steps: the search ends on the budget, not on the path.
      result.stop = KeepStop{KeepStop::Kind::kTimeBudget};
      std::array<bool, kNumLegs> every{};
      every.fill(true);
      finish(t_ok, every, ok_stretch);
      return result;
    }
    const double t = std::min(end, t_ok + ctx.config.path_step_s);
    const KeepCheck next = KeepAt(ctx, path, node, t);
    if (next.ok()) {
      t_ok = t;
      ok_stretch = next.stretch;
      continue;
    }
    // Bisect to the last keepable time.
    double lo = t_ok, hi = t;
    KeepCheck at_hi = next;
    while (hi - lo > ctx.config.step_time_resolution_s) {
      const double mid = 0.5 * (lo + hi);
      KeepCheck at_mid = KeepAt(ctx, path, node, mid);
      if (at_mid.ok()) {
        lo = mid;
      } else {
        hi = mid;
        at_hi = std::move(at_mid);
      }
    }
    result.stop = at_hi.failure;
    finish(lo, at_hi.failing, at_hi.stretch);
    return result;
  }
  result.reached_end = true;
  finish(end, std::array<bool, kNumLegs>{}, ok_stretch);
  return result;
}

}  // namespace rbcp::contact_planner_detail
