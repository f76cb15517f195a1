#include "step.h"

#include <algorithm>
#include <array>
#include <limits>
#include <string_view>
#include <vector>

#include "crawl_order.h"
#include "foothold_query.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "stance_checks.h"

namespace rbcp::contact_planner_detail {
namespace {

/// The node after `parent` steps option.leg to `feet` with the base at `base` and the joints q.
Node ChildNode(const CrawlProfile& profile, const Node& parent, const Node::Option& option,
               const StanceBase& base, const JointVector& q,
               const std::array<FootContact, kNumLegs>& feet, const Eigen::Vector3d& shift) {
  const int j = Index(option.leg);
  Node child;
  child.state.base_position = base.base_W.translation();
  child.state.base_rpy = base.rpy;
  child.state.joints = q;
  child.state.feet = feet;
  child.state.moving_leg = j;
  child.t = option.t;
  // The body moves back towards the path once the swing's foot is down: a body kept shifted
  // sideways and back drags the other feet out of their workspace as the trunk advances.
  child.shift = shift;
  child.shift.head<2>() *= profile.keep_fraction;
  const bool advanced = option.t > parent.t + 1e-9;
  child.steps_at_time = advanced ? 1 : parent.steps_at_time + 1;
  if (advanced) child.stepped_at_time.fill(false);
  else child.stepped_at_time = parent.stepped_at_time;
  child.stepped_at_time[static_cast<std::size_t>(j)] = true;
  return child;
}

}  // namespace

std::optional<StepAttempt> LiftOffFailure(const PlannerContext& ctx, const WholeBodyState& from, Leg leg,
                                          const StanceBase& base, const JointVector& q_pre) {
  const int j = Index(leg);
  const auto invalid = [](StepFailure::Kind kind, StanceVerdict verdict = {},
                          std::optional<Leg> blocking = std::nullopt) {
    return StepAttempt{StepFailure(kind, std::move(verdict)), blocking, Node{}};
  };
  // A stance leg that meets the terrain, at lift-off or as the body moves, is re-placed first.
  const auto blocking_leg = [&](const StanceVerdict& v) {
    return v.check == StanceCheck::kCollision && v.leg != leg ? v.leg : std::nullopt;
  };
  StanceVerdict hit = ctx.stance.LiftOffCollision(base.base_W, q_pre, leg);
  if (!hit.ok()) {
    const std::optional<Leg> blocking = blocking_leg(hit);
    return invalid(StepFailure::Kind::kLiftOffCollision, std::move(hit), blocking);
  }
  const Eigen::Vector3d com_pre = CoM(ctx, base.base_W, q_pre);
  if (!SupportHolds(ctx, from.feet, j, com_pre)) return invalid(StepFailure::Kind::kLiftOffSupport);
  if (StanceVerdict torque = Torques(ctx, base.base_W, q_pre, from.feet, j, com_pre); !torque.ok()) {
    return invalid(StepFailure::Kind::kLiftOffTorque, std::move(torque));
  }
  StanceVerdict shift = ctx.stance.CheckShift(from.base_position, from.base_rpy, base.base_W, base.rpy, from.feet, j);
  if (!shift.ok()) {
    const std::optional<Leg> blocking = blocking_leg(shift);
    return invalid(StepFailure::Kind::kTransit, std::move(shift), blocking);
  }
  return std::nullopt;
}

std::optional<CandidateFailure> TouchDownStanceFailure(const PlannerContext& ctx, const Eigen::Isometry3d& base,
                                                       const JointVector& q, const Feet& feet, int swing,
                                                       const Eigen::Vector3d& com_W) {
  const EquilibriumResult eq = ctx.equilibrium.Robustness(Contacts(feet, -1), com_W);
  if (!ctx.equilibrium.MeetsThreshold(eq)) {
    CandidateFailure failure(CandidateFailure::Kind::kRobustness);
    failure.robustness_N = eq.robustness_N;
    return failure;
  }
  if (StanceVerdict four = Torques(ctx, base, q, feet, -1, com_W); !four.ok()) {
    return CandidateFailure(CandidateFailure::Kind::kFourFootTorque, std::move(four));
  }
  if (StanceVerdict three = Torques(ctx, base, q, feet, swing, com_W); !three.ok()) {
    return CandidateFailure(CandidateFailure::Kind::kThreeFootTorque, std::move(three));
  }
  return std::nullopt;
}

namespace {

/// The swing of `swing` from its foothold in from_feet to to_W as the planner checks it.
SwingTrajectory PlannedSwing(const PlannerContext& ctx, const Feet& from_feet, int swing, const Eigen::Vector3d& to_W,
                             const Eigen::Isometry3d& base, const JointVector& q) {
  return ctx.stance.PlanSwing(static_cast<Leg>(swing), from_feet[static_cast<std::size_t>(swing)].position, to_W, base, q,
                              SwingSearch::kFirstClear);
}

}  // namespace

std::optional<CandidateFailure> SwingClearanceFailure(const PlannerContext& ctx, const Feet& from_feet, int swing,
                                                      const Eigen::Vector3d& to_W, const Eigen::Isometry3d& base,
                                                      const JointVector& q) {
  ++ctx.stats.swing_checks;
  StanceVerdict v =
      ctx.stance.SwingClearance(PlannedSwing(ctx, from_feet, swing, to_W, base, q), static_cast<Leg>(swing));
  if (v.ok()) return std::nullopt;
  return CandidateFailure(CandidateFailure::Kind::kSwing, std::move(v));
}

void AttachSwings(const PlannerContext& ctx, std::vector<WholeBodyState>& states) {
  if (!states.empty()) {  // the first state is where the plan starts: no swing reaches it
    states.front().swing_apex_z = std::numeric_limits<double>::quiet_NaN();
    states.front().swing_bow.setZero();
  }
  for (std::size_t k = 1; k < states.size(); ++k) {
    WholeBodyState& s = states[k];
    const std::size_t j = static_cast<std::size_t>(s.moving_leg);
    const SwingTrajectory path = PlannedSwing(ctx, states[k - 1].feet, s.moving_leg, s.feet[j].position, BasePose(s), s.joints);
    s.swing_apex_z = std::numeric_limits<double>::quiet_NaN();
    s.swing_bow.setZero();
    if (ctx.stance.SwingClearance(path, static_cast<Leg>(s.moving_leg)).ok()) {
      s.swing_apex_z = path.Apex();
      s.swing_bow = path.Bow();
    }
  }
}

int NumShiftStarts(const ContactPlannerConfig& config) {
  return 2 + static_cast<int>(config.base_shift.lateral_offsets_m.size() + config.base_shift.height_offsets_m.size());
}

Eigen::Vector3d ShiftStart(const ContactPlannerConfig& config, const Node& parent, int shift_start) {
  RBCP_CHECK(shift_start >= 0 && shift_start < NumShiftStarts(config), "shift start " + std::to_string(shift_start));
  const BaseShiftConfig& bs = config.base_shift;
  if (shift_start == 0) return parent.shift;
  if (shift_start == 1) return Eigen::Vector3d::Zero();
  const std::size_t k = static_cast<std::size_t>(shift_start - 2);
  if (k < bs.lateral_offsets_m.size()) return {0.0, bs.lateral_offsets_m[k], 0.0};
  return {0.0, 0.0, bs.height_offsets_m.at(k - bs.lateral_offsets_m.size())};
}

SwingShiftResult SwingShift(const PlannerContext& ctx, const PathPose& pose, const Node& parent, Leg swing,
                            const Eigen::Vector3d& start) {
  const BaseShiftConfig& bs = ctx.config.base_shift;
  const int skip = Index(swing);
  SwingShiftResult result;
  const auto base_at = [&](const Eigen::Vector3d& s) { return StanceBaseAt(ctx, pose, s, parent.state.feet, skip); };
  const std::vector<Eigen::Vector3d> stance = FeetPositions(parent.state.feet, skip);
  RBCP_CHECK(stance.size() == 3, "a swing stands on three feet");
  const std::array<Eigen::Vector2d, 3> tri = {stance[0].head<2>(), stance[1].head<2>(), stance[2].head<2>()};
  const double required = ctx.stance.Config().support_margin_m;
  const auto eroded = ErodeTriangle(tri, required + bs.shift_extra_margin_m);
  // A triangle the CoM cannot get into is widened by the leg before this one in the crawl.
  const Leg widening_leg = CrawlPrevious(swing);
  if (!eroded) {
    result.failure = StepFailure(StepFailure::Kind::kTriangleTooSmall);
    result.blocking = widening_leg;
    return result;
  }
  const Eigen::Matrix3d R = Yaw(pose.yaw);
  const double max_shift = bs.max_base_shift_m;
  const auto clamp = [&](Eigen::Vector3d s) {
    if (s.head<2>().norm() > max_shift) s.head<2>() *= max_shift / s.head<2>().norm();
    return s;
  };
  // Start from `start`; fall back on the current horizontal shift when the feet cannot be
  // reached from there.
  Eigen::Vector3d shift = clamp(start);
  StanceBase base = base_at(shift);
  std::optional<JointVector> q_stance = SolveStance(ctx, base.base_W, parent.state.feet, skip);
  if (!q_stance) {
    shift = clamp(Eigen::Vector3d(parent.shift.x(), parent.shift.y(), start.z()));
    base = base_at(shift);
    q_stance = SolveStance(ctx, base.base_W, parent.state.feet, skip);
    if (!q_stance) {
      result.failure = StepFailure(StepFailure::Kind::kStanceOutOfReach);
      return result;
    }
  }
  JointVector q = *q_stance;
  bool stuck = false;  // an update found no reachable stance
  for (int iter = 0; iter < 6; ++iter) {
    const Eigen::Vector3d com = CoM(ctx, base.base_W, q);
    if (SupportPolygonMargin(stance, com) >= required + 0.5 * bs.shift_extra_margin_m) {
      result.shift = shift;
      result.base = base;
      result.q = q;
      return result;
    }
    const Eigen::Vector2d goal = ClosestPointInTriangle(*eroded, com.head<2>());
    const Eigen::Vector3d delta = R.transpose() * Eigen::Vector3d(goal.x() - com.x(), goal.y() - com.y(), 0.0);
    bool moved = false;
    // Each update is tried at the same height, then lowered and raised by height_step_m: a
    // stance spread over stairs or blocks often needs the body lower or higher to reach.
    const double dz_step = bs.height_step_m;
    for (double scale = 1.0; scale > 0.1 && !moved; scale *= 0.5) {
      for (const double dz : {0.0, -dz_step, dz_step}) {
        if (dz != 0.0 && dz_step <= 0.0) break;
        Eigen::Vector3d trial = clamp(shift + scale * delta);
        trial.z() += dz;
        const StanceBase trial_base = base_at(trial);
        if (const std::optional<JointVector> q_trial = SolveStance(ctx, trial_base.base_W, parent.state.feet, skip)) {
          shift = trial;
          base = trial_base;
          q = *q_trial;
          moved = true;
          break;
        }
      }
    }
    if (!moved) {
      stuck = true;
      break;
    }
  }
  if (SupportPolygonMargin(stance, CoM(ctx, base.base_W, q)) >= required) {
    result.shift = shift;
    result.base = base;
    result.q = q;
    return result;
  }
  if (stuck) {
    result.failure = StepFailure(StepFailure::Kind::kShiftedOutOfReach);
  } else {
    result.failure = StepFailure(StepFailure::Kind::kCoMNotInside);
    result.failure->margin_m = required;
    result.blocking = widening_leg;
  }
  return result;
}

namespace {

StepAttempt Failed(StepFailure failure) { return StepAttempt{std::move(failure), std::nullopt, Node{}}; }

/// The pose whose reference foot position a step aims at: the path pose the option's lead ahead,
/// or the path end for a goal step.
PathPose TargetPose(const PlannerContext& ctx, const PathTrack& path, const Node::Option& option) {
  if (option.goal_step) return path.At(path.End());
  const FootholdConfig& fc = ctx.config.foothold;
  const int k = option.lead_factor_index;
  RBCP_CHECK(k >= 0 && static_cast<std::size_t>(k) < fc.lead_time_factors.size(), "lead index " + std::to_string(k));
  const double lead = fc.lead_time_s * fc.lead_time_factors[static_cast<std::size_t>(k)];
  return LeadPose(path, option.t, lead, fc.max_lead_yaw_rad);
}

/// One step's search through its foothold candidates: what every candidate is tested against
/// (the stance before lift-off at the swing's body shift) and what the candidates tested so far
/// found.
struct CandidateSearch {
  const PlannerContext& ctx;
  const Node& parent;
  const Node::Option& option;
  const SwingShiftResult& swing;  ///< the body shift, base pose and joints before lift-off
  PathPose ahead_pose;            ///< the look-ahead's path pose (lead_time_s after the step)
  std::vector<Eigen::Vector3d> swing_failed;  ///< footholds whose swing cannot keep clear
  int stability_evaluations = 0;              ///< candidates tested for stability
  std::optional<CandidateFailure> last_reject;
};

/// Whether a candidate is passed over untested: too short a step, too close to another foot, or
/// near a foothold whose swing failed.
bool PassedOver(const CandidateSearch& s, const Eigen::Vector3d& foothold) {
  const FootholdConfig& fc = s.ctx.config.foothold;
  const int j = Index(s.option.leg);
  if ((foothold - s.parent.state.feet[static_cast<std::size_t>(j)].position).norm() < fc.min_step_length_m) return true;
  if (!FarEnoughFromFeet(s.ctx, s.parent.state.feet, j, foothold)) return true;
  return std::any_of(s.swing_failed.begin(), s.swing_failed.end(), [&](const Eigen::Vector3d& f) {
    return (f - foothold).norm() < fc.swing_failure_radius_m;
  });
}

/// The tests of a candidate before its equilibrium: workspace, kinematics, the CoM in the swing
/// triangle at touch-down, leg and self-collision, and the look-ahead. Sets *q_post and
/// *com_post (the joints and CoM at touch-down) as far as it gets.
std::optional<CandidateFailure> PlacementFailure(const CandidateSearch& s, const Eigen::Vector3d& foothold,
                                                 JointVector* q_post, Eigen::Vector3d* com_post) {
  const PlannerContext& ctx = s.ctx;
  const Leg leg = s.option.leg;
  const Eigen::Isometry3d& base = s.swing.base.base_W;
  using Kind = CandidateFailure::Kind;
  const Eigen::Vector3d p_B = base.inverse() * foothold;
  if (WorkspaceRatio(ctx, leg, p_B) > 1.0) return CandidateFailure(Kind::kWorkspace);
  const IkResult ik = ctx.robot.SolveLegIk(leg, p_B);
  if (!ik.ok() || !ctx.robot.KneeBent(ik.q)) return CandidateFailure(Kind::kKinematics);
  *q_post = s.swing.q;
  SetLegJoints(*q_post, leg, ik.q);
  *com_post = CoM(ctx, base, *q_post);
  if (!SupportHolds(ctx, s.parent.state.feet, Index(leg), *com_post)) return CandidateFailure(Kind::kTouchDownSupport);
  if (ctx.stance.TerrainCollision().CheckLeg(leg, base, ik.q, true).collision) {
    return CandidateFailure(Kind::kLegCollision);
  }
  // The lift-off stance passed the whole self-collision test; only the stepping leg moved.
  if (ctx.stance.ExactCollision().CheckSelf(*q_post, leg).collision) return CandidateFailure(Kind::kSelfCollision);
  // Look-ahead: the foot must stay keepable (workspace, kinematics, no collision) at the path
  // pose lead_time_s later, so it is not placed where the advancing trunk would at once drag
  // its shank into a riser or a block edge.
  if (!s.option.goal_step) {
    std::array<FootContact, kNumLegs> ahead_feet = s.parent.state.feet;
    ahead_feet[static_cast<std::size_t>(Index(leg))].position = foothold;
    const Eigen::Isometry3d ahead =
        StanceBaseAt(ctx, s.ahead_pose, Eigen::Vector3d(0.0, 0.0, s.swing.shift.z()), ahead_feet).base_W;
    if (KeepLeg(ctx, leg, ahead, foothold).failure != KeepFailure::kNone) return CandidateFailure(Kind::kNotKeepable);
  }
  return std::nullopt;
}

/// Tests candidate c: the step when it passes; a failure when the step ends with it (the
/// stability cap, too many swings that cannot keep clear); nullopt to go on with the next one.
std::optional<StepAttempt> TestCandidate(CandidateSearch& s, const Candidate& c, const CrawlProfile& profile) {
  const PlannerContext& ctx = s.ctx;
  const FootholdConfig& fc = ctx.config.foothold;
  const int j = Index(s.option.leg);
  ++ctx.stats.candidates_evaluated;
  if (PassedOver(s, c.foothold)) return std::nullopt;
  JointVector q_post;
  Eigen::Vector3d com_post;
  if (std::optional<CandidateFailure> failure = PlacementFailure(s, c.foothold, &q_post, &com_post)) {
    s.last_reject = std::move(failure);
    return std::nullopt;
  }
  if (s.stability_evaluations >= fc.max_stability_evaluations) {
    StepFailure capped{StepFailure::Kind::kStabilityCap};
    capped.count = static_cast<std::size_t>(s.stability_evaluations);
    capped.last = s.last_reject;
    return Failed(std::move(capped));
  }
  ++s.stability_evaluations;
  ++ctx.stats.stability_evaluations;
  const Eigen::Isometry3d& base = s.swing.base.base_W;
  std::array<FootContact, kNumLegs> feet = s.parent.state.feet;
  feet[static_cast<std::size_t>(j)].position = c.foothold;
  feet[static_cast<std::size_t>(j)].normal = ctx.surfaces[static_cast<std::size_t>(c.surface)].Normal();
  if (std::optional<CandidateFailure> failure = TouchDownStanceFailure(ctx, base, q_post, feet, j, com_post)) {
    s.last_reject = std::move(failure);
    return std::nullopt;
  }
  // The swing the controller will walk, from this base pose: the last test, and the dearest.
  if (std::optional<CandidateFailure> failure =
          SwingClearanceFailure(ctx, s.parent.state.feet, j, c.foothold, base, q_post)) {
    s.last_reject = std::move(failure);
    s.swing_failed.push_back(c.foothold);
    if (static_cast<int>(s.swing_failed.size()) < fc.max_swing_failures) return std::nullopt;
    StepFailure unclear{StepFailure::Kind::kSwingFailures};
    unclear.count = s.swing_failed.size();
    unclear.last = s.last_reject;
    return Failed(std::move(unclear));
  }
  return StepAttempt{std::nullopt, std::nullopt,
                     ChildNode(profile, s.parent, s.option, s.swing.base, q_post, feet, s.swing.shift)};
}

/// The candidates toward the target pose's reference foot, until one passes: those near the
/// target first (most steps end there, and the database query is the planner's main cost), then
/// the rest of the workspace.
StepAttempt SearchCandidates(CandidateSearch& s, const PathPose& target_pose, const CrawlProfile& profile) {
  const PlannerContext& ctx = s.ctx;
  const Leg leg = s.option.leg;
  const Eigen::Vector3d target = PathBasePose(target_pose) * ctx.robot.ReferenceFootPosition(leg);
  const double near_half = ctx.config.foothold.near_query_half_m;
  std::size_t candidates_seen = 0;
  for (int stage = near_half > 0.0 ? 0 : 1; stage < 2; ++stage) {
    const std::vector<Candidate> cands =
        RankedCandidates(ctx, leg, s.swing.base.base_W, target, target_pose.yaw, stage == 0 ? near_half : 0.0);
    if (ctx.budget.Exhausted()) return Failed(StepFailure(StepFailure::Kind::kTimeBudget));
    candidates_seen += stage == 0 ? cands.size() : 0;
    for (const Candidate& c : cands) {
      if (stage == 1 && near_half > 0.0 && ((c.foothold - target).head<2>().cwiseAbs().array() < near_half).all()) {
        continue;  // evaluated in the first stage
      }
      if (stage == 1) ++candidates_seen;
      if (ctx.budget.Exhausted()) return Failed(StepFailure(StepFailure::Kind::kTimeBudget));
      if (std::optional<StepAttempt> end = TestCandidate(s, c, profile)) return std::move(*end);
    }
  }
  StepFailure none{StepFailure::Kind::kNoFoothold};
  none.count = candidates_seen;
  none.last = s.last_reject;
  return Failed(std::move(none));
}

}  // namespace

StepAttempt TryStep(const PlannerContext& ctx, const PathTrack& path, const Node& parent, const Node::Option& option,
                    const CrawlProfile& profile) {
  const FootholdConfig& fc = ctx.config.foothold;
  ++ctx.stats.step_attempts;
  SwingShiftResult swing =
      SwingShift(ctx, path.At(option.t), parent, option.leg, ShiftStart(ctx.config, parent, option.shift_start));
  if (!swing.ok()) return {std::move(swing.failure), swing.blocking, Node{}};
  // The stance before lift-off: collision, swing triangle, torques of the three-foot stance.
  if (std::optional<StepAttempt> invalid = LiftOffFailure(ctx, parent.state, option.leg, swing.base, swing.q)) {
    return std::move(*invalid);
  }
  const PathPose target_pose = TargetPose(ctx, path, option);
  const PathPose ahead_pose = LeadPose(path, option.t, fc.lead_time_s, fc.max_lead_yaw_rad);
  CandidateSearch search{ctx, parent, option, swing, ahead_pose, {}, 0, std::nullopt};
  return SearchCandidates(search, target_pose, profile);
}

}  // namespace rbcp::contact_planner_detail
