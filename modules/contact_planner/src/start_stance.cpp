#include "start_stance.h"

#include <array>
#include <vector>

#include "crawl_order.h"
#include "foothold_query.h"
#include "path_track.h"
#include "rbcp/core/format.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "stance_checks.h"

namespace rbcp::contact_planner_detail {

std::string StandingFailure::Describe() const {
  switch (kind) {
    case Kind::kTimeBudget: return "time budget exhausted";
    case Kind::kNoFoothold:
      return std::string("no valid foothold for ") + std::string(LegName(leg)) + " near its reference position (" +
             std::to_string(candidates) + " candidates)";
    case Kind::kTrunkCollision: return "trunk collides with the terrain";
    case Kind::kSelfCollision: return "self-collision " + collision.first_shape + " / " + collision.obstacle;
    case Kind::kUnstable:
      return "standing stance not statically stable (robustness " + FixedNumber(robustness_N, 2) + " N)";
    case Kind::kSupport: return verdict.detail;
    case Kind::kTorque: return "standing stance: " + verdict.detail;
  }
  return "unknown standing failure";
}

StandingResult StandingAt(const PlannerContext& ctx, const Eigen::Vector3d& base_position, double yaw) {
  const auto fail = [](StandingFailure failure) { return StandingResult{std::nullopt, std::move(failure)}; };
  using Kind = StandingFailure::Kind;
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
    const Eigen::Vector3d target = base * ctx.robot.ReferenceFootPosition(leg);
    const std::vector<Candidate> cands = RankedCandidates(ctx, leg, base, target, yaw);
    if (ctx.budget.Exhausted()) return fail(StandingFailure(Kind::kTimeBudget));
    bool found = false;
    for (const Candidate& c : cands) {
      ++ctx.stats.candidates_evaluated;
      if (!FarEnoughFromFeet(ctx, state.feet, placed, c.foothold)) continue;
      const LegKeep keep = KeepLeg(ctx, leg, base, c.foothold);
      if (keep.failure != KeepFailure::kNone) continue;
      state.feet[i].position = c.foothold;
      state.feet[i].normal = ctx.surfaces[static_cast<std::size_t>(c.surface)].Normal();
      SetLegJoints(q, leg, keep.q);
      placed[i] = true;
      found = true;
      break;
    }
    if (!found) {
      StandingFailure none(Kind::kNoFoothold);
      none.leg = leg;
      none.candidates = cands.size();
      return fail(std::move(none));
    }
  }
  state.joints = q;
  if (ctx.stance.TerrainCollision().CheckTrunk(base).collision) return fail(StandingFailure(Kind::kTrunkCollision));
  if (CollisionReport self = ctx.stance.ExactCollision().CheckSelf(q); self.collision) {
    StandingFailure touching(Kind::kSelfCollision);
    touching.collision = std::move(self);
    return fail(std::move(touching));
  }
  const Eigen::Vector3d com = CoM(ctx, base, q);
  ++ctx.stats.stability_evaluations;
  const EquilibriumResult eq = ctx.equilibrium.Robustness(Contacts(state.feet, -1), com);
  if (!ctx.equilibrium.MeetsThreshold(eq)) {
    StandingFailure unstable(Kind::kUnstable);
    unstable.robustness_N = eq.robustness_N;
    return fail(std::move(unstable));
  }
  if (StanceVerdict support = ctx.stance.Support(state.feet, -1, com); !support.ok()) {
    return fail(StandingFailure(Kind::kSupport, std::move(support)));
  }
  if (StanceVerdict torque = Torques(ctx, base, q, state.feet, -1, com); !torque.ok()) {
    return fail(StandingFailure(Kind::kTorque, std::move(torque)));
  }
  return {state, std::nullopt};
}

}  // namespace rbcp::contact_planner_detail
