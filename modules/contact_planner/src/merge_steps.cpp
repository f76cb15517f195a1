#include "merge_steps.h"

#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "foothold_query.h"
#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "stance_checks.h"
#include "step.h"

namespace rbcp::contact_planner_detail {
namespace {

/// Whether the step from `prev` to `cur` (cur.moving_leg swings, the base moves to cur's pose
/// first) is valid at lift-off and in the swing: every foot of `prev` reachable at cur's pose
/// (the swing foot within the lift-off margin), the search's lift-off checks (LiftOffFailure) and
/// its swing check (SwingClearanceFailure).
bool LiftOffValid(const PlannerContext& ctx, const WholeBodyState& prev, const WholeBodyState& cur) {
  const int j = cur.moving_leg;
  StanceBase base;
  base.base_W = BasePose(cur);
  base.rpy = cur.base_rpy;
  const std::optional<JointVector> q_pre = SolveStance(ctx, base.base_W, prev.feet, j);
  if (!q_pre || LiftOffFailure(ctx, prev, kAllLegs[static_cast<std::size_t>(j)], base, *q_pre)) return false;
  return !SwingClearanceFailure(ctx, prev.feet, j, cur.feet[static_cast<std::size_t>(j)].position, base.base_W,
                                cur.joints);
}

/// `cur` with its base at `base`, checked at touch-down of its step from `prev`: the `changed`
/// leg's foot and the new foothold within the workspace box scaled by merge.workspace_scale (the
/// search placed them for other poses), every foot within the margins, the new foothold's leg
/// clear of the terrain and apart from the other feet, the touch-down triangle, and the search's
/// touch-down stance checks (TouchDownStanceFailure). Its joints are solved again. nullopt when
/// invalid.
std::optional<WholeBodyState> AtTouchDown(const PlannerContext& ctx, const WholeBodyState& prev, WholeBodyState cur,
                                          int changed, const StanceBase& base) {
  const int j = cur.moving_leg;
  const Leg swing = kAllLegs[static_cast<std::size_t>(j)];
  const Eigen::Isometry3d T_BW = base.base_W.inverse();
  const double box = ctx.config.merge.workspace_scale;
  const Eigen::Vector3d& new_foot = cur.feet[static_cast<std::size_t>(j)].position;
  if (WorkspaceRatio(ctx, kAllLegs[static_cast<std::size_t>(changed)],
                     T_BW * cur.feet[static_cast<std::size_t>(changed)].position) > box ||
      WorkspaceRatio(ctx, swing, T_BW * new_foot) > box) {
    return std::nullopt;
  }
  const std::optional<JointVector> q = SolveStance(ctx, base.base_W, cur.feet, -1);
  if (!q) return std::nullopt;
  if (ctx.stance.TerrainCollision().CheckLeg(swing, base.base_W, LegJoints(*q, swing), true).collision) return std::nullopt;
  if ((new_foot - prev.feet[static_cast<std::size_t>(j)].position).norm() < ctx.config.foothold.min_step_length_m) {
    return std::nullopt;
  }
  if (!FarEnoughFromFeet(ctx, cur.feet, j, new_foot)) return std::nullopt;
  if (ctx.stance.ExactCollision().CheckSelf(*q).collision) return std::nullopt;
  const Eigen::Vector3d com = CoM(ctx, base.base_W, *q);
  if (!SupportHolds(ctx, prev.feet, j, com)) return std::nullopt;
  if (TouchDownStanceFailure(ctx, base.base_W, *q, cur.feet, j, com)) return std::nullopt;
  cur.base_position = base.base_W.translation();
  cur.base_rpy = base.rpy;
  cur.joints = *q;
  return cur;
}

/// `cur`, whose `changed` leg now stands elsewhere, made valid at touch-down and at lift-off
/// from `prev`: with cur's own base pose, else with the body shift of cur's swing searched again
/// from there with the feet of prev (the changed foot moves the swing triangle and the base
/// height). nullopt when neither is valid.
std::optional<WholeBodyState> Revalidated(const PlannerContext& ctx, const WholeBodyState& prev,
                                          const WholeBodyState& cur, int changed) {
  StanceBase own;
  own.base_W = BasePose(cur);
  own.rpy = cur.base_rpy;
  if (std::optional<WholeBodyState> valid = AtTouchDown(ctx, prev, cur, changed, own)) {
    if (LiftOffValid(ctx, prev, *valid)) return valid;
  }
  Node parent;
  parent.state = prev;
  const SwingShiftResult shifted = SwingShift(ctx, PathPose{cur.base_position, cur.base_rpy.z()}, parent,
                                              kAllLegs[static_cast<std::size_t>(cur.moving_leg)], Eigen::Vector3d::Zero());
  if (!shifted.ok()) return std::nullopt;
  std::optional<WholeBodyState> valid = AtTouchDown(ctx, prev, cur, changed, shifted.base);
  if (valid && LiftOffValid(ctx, prev, *valid)) return valid;
  return std::nullopt;
}

/// The states replacing k .. m (one fewer) when leg L = states[k].moving_leg, stepping A -> B at
/// k and B -> C at m (its next step), instead stands on A until it steps A -> C at m
/// (`arrive_early` false), or steps A -> C at k (true). nullopt when the plan is not valid so.
std::optional<std::vector<WholeBodyState>> WithoutStep(const PlannerContext& ctx,
                                                       const std::vector<WholeBodyState>& states, std::size_t k,
                                                       bool arrive_early) {
  const int leg = states[k].moving_leg;
  std::size_t m = k + 1;
  while (m < states.size() && states[m].moving_leg != leg) ++m;
  if (m >= states.size()) return std::nullopt;  // the leg's last step: it reaches the goal stance
  const std::size_t l = static_cast<std::size_t>(leg);
  const FootContact& from = states[k - 1].feet[l];
  const FootContact& to = states[m].feet[l];
  if ((to.position - from.position).norm() < ctx.config.foothold.min_step_length_m) return std::nullopt;
  const FootContact held = arrive_early ? to : from;
  std::vector<WholeBodyState> out;
  const WholeBodyState* prev = &states[k - 1];
  for (std::size_t i = arrive_early ? k : k + 1; i < m; ++i) {
    WholeBodyState cur = states[i];
    cur.feet[l] = held;
    std::optional<WholeBodyState> valid = Revalidated(ctx, *prev, cur, leg);
    if (!valid || IsAvoided(ctx.avoided, *prev, *valid)) return std::nullopt;
    out.push_back(std::move(*valid));
    prev = &out.back();
  }
  // The step after the rewritten ones lifts off from the last of them.
  const std::size_t next = arrive_early ? m + 1 : m;
  if (next < states.size() && (!LiftOffValid(ctx, *prev, states[next]) || IsAvoided(ctx.avoided, *prev, states[next]))) {
    return std::nullopt;
  }
  if (!arrive_early) out.push_back(states[m]);
  return out;
}

}  // namespace

std::vector<WholeBodyState> MergeSteps(const PlannerContext& ctx, std::vector<WholeBodyState> states, int* removed) {
  int count = 0;
  bool changed = true;
  while (changed) {
    changed = false;
    for (std::size_t k = 1; k < states.size(); ++k) {
      if (ctx.budget.Exhausted()) break;
      for (const bool arrive_early : {false, true}) {
        std::optional<std::vector<WholeBodyState>> rewritten = WithoutStep(ctx, states, k, arrive_early);
        if (!rewritten) continue;
        // States k .. k + n (the leg's next step) become the n rewritten ones.
        const std::size_t n = rewritten->size();
        for (std::size_t i = 0; i < n; ++i) states[k + i] = std::move((*rewritten)[i]);
        states.erase(states.begin() + static_cast<std::ptrdiff_t>(k + n));
        ++count;
        changed = true;
        break;
      }
    }
  }
  if (removed) *removed = count;
  return states;
}

std::optional<std::vector<WholeBodyState>> FromStart(const PlannerContext& ctx,
                                                     const std::vector<WholeBodyState>& states,
                                                     const WholeBodyState& start) {
  if (states.empty() || start.base_position != states[0].base_position || start.base_rpy != states[0].base_rpy) {
    return std::nullopt;
  }
  int changed = -1;
  for (int l = 0; l < kNumLegs; ++l) {
    const std::size_t i = static_cast<std::size_t>(l);
    if (start.feet[i].position == states[0].feet[i].position) continue;
    if (changed >= 0) return std::nullopt;
    changed = l;
  }
  std::vector<WholeBodyState> out = states;
  out[0].feet = start.feet;
  const std::optional<JointVector> q = SolveStance(ctx, BasePose(out[0]), out[0].feet, -1);
  if (!q) return std::nullopt;
  out[0].joints = *q;
  if (changed < 0) return out;
  const FootContact held = start.feet[static_cast<std::size_t>(changed)];
  for (std::size_t i = 1; i < out.size(); ++i) {
    if (out[i].moving_leg == changed) {
      if (!LiftOffValid(ctx, out[i - 1], out[i])) return std::nullopt;
      return out;
    }
    WholeBodyState cur = out[i];
    cur.feet[static_cast<std::size_t>(changed)] = held;
    std::optional<WholeBodyState> valid = Revalidated(ctx, out[i - 1], cur, changed);
    if (!valid) return std::nullopt;
    out[i] = std::move(*valid);
  }
  return std::nullopt;  // the leg never steps again
}

std::optional<std::vector<WholeBodyState>> OnTerrain(const PlannerContext& ctx, const std::vector<WholeBodyState>& states,
                                                     double max_offset_m) {
  if (states.empty()) return std::nullopt;
  std::vector<WholeBodyState> out = states;
  for (const WholeBodyState& state : out) {
    for (const FootContact& foot : state.feet) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const ConvexPolygon3d& surface : ctx.surfaces) {
        nearest = std::min(nearest, (surface.ClosestPoint(foot.position) - foot.position).norm());
      }
      if (!(nearest <= max_offset_m)) return std::nullopt;
    }
  }
  const std::optional<JointVector> q = SolveStance(ctx, BasePose(out[0]), out[0].feet, -1);
  if (!q) return std::nullopt;
  out[0].joints = *q;
  for (std::size_t i = 1; i < out.size(); ++i) {
    StanceBase own;
    own.base_W = BasePose(out[i]);
    own.rpy = out[i].base_rpy;
    std::optional<WholeBodyState> valid = AtTouchDown(ctx, out[i - 1], out[i], out[i].moving_leg, own);
    if (!valid || !LiftOffValid(ctx, out[i - 1], *valid)) return std::nullopt;
    out[i] = std::move(*valid);
  }
  return out;
}

}  // namespace rbcp::contact_planner_detail
