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
  const auto invalid = [](std::string why, std::optional<Leg> blocking = std::nullopt) {
    return StepAttempt{StepOutcome::kPoseInvalid, std::move(why), blocking, Node{}};
  };
  const StanceVerdict hit = ctx.stance.LiftOffCollision(base.base_W, q_pre, leg);
  if (!hit.ok()) {
    std::optional<Leg> blocking = hit.check == StanceCheck::kCollision ? hit.leg : std::nullopt;
    if (blocking == leg) blocking.reset();
    return invalid(std::string(ToString(hit.check)) + " before lift-off (" + hit.detail + ")", blocking);
  }
  const Eigen::Vector3d com_pre = CoM(ctx, base.base_W, q_pre);
  if (!SupportHolds(ctx, from.feet, j, com_pre)) return invalid("CoM too close to the swing support triangle at lift-off");
  if (const StanceVerdict torque = Torques(ctx, base.base_W, q_pre, from.feet, j, com_pre); !torque.ok()) {
    return invalid("three-foot stance at lift-off: " + torque.detail);
  }
  const StanceVerdict shift =
      ctx.stance.CheckShift(from.base_position, from.base_rpy, base.base_W, base.rpy, from.feet, j);
  if (!shift.ok()) {
    // A stance leg that meets the terrain as the body moves is re-placed first.
    std::optional<Leg> blocking = shift.check == StanceCheck::kCollision ? shift.leg : std::nullopt;
    if (blocking == leg) blocking.reset();
    return invalid("while the body moves to the step pose: " + shift.detail, blocking);
  }
  return std::nullopt;
}

std::string TouchDownStanceProblem(const PlannerContext& ctx, const Eigen::Isometry3d& base, const JointVector& q,
                                   const Feet& feet, int swing, const Eigen::Vector3d& com_W) {
  const EquilibriumResult eq = ctx.equilibrium.Robustness(Contacts(feet, -1), com_W);
  if (!ctx.equilibrium.MeetsThreshold(eq)) return "robustness " + FixedNumber(eq.robustness_N, 2) + " N";
  if (const StanceVerdict four = Torques(ctx, base, q, feet, -1, com_W); !four.ok()) {
    return "four-foot stance: " + four.detail;
  }
  if (const StanceVerdict three = Torques(ctx, base, q, feet, swing, com_W); !three.ok()) {
    return "three-foot stance at touch-down: " + three.detail;
  }
  return "";
}

namespace {

/// The swing of `swing` from its foothold in from_feet to to_W as the planner checks it.
SwingTrajectory PlannedSwing(const PlannerContext& ctx, const Feet& from_feet, int swing, const Eigen::Vector3d& to_W,
                             const Eigen::Isometry3d& base, const JointVector& q) {
  return ctx.stance.PlanSwing(static_cast<Leg>(swing), from_feet[static_cast<std::size_t>(swing)].position, to_W, base, q,
                              SwingSearch::kFirstClear);
}

}  // namespace

std::string SwingProblem(const PlannerContext& ctx, const Feet& from_feet, int swing, const Eigen::Vector3d& to_W,
                         const Eigen::Isometry3d& base, const JointVector& q) {
  ++ctx.stats.swing_checks;
  const StanceVerdict v =
      ctx.stance.SwingClearance(PlannedSwing(ctx, from_feet, swing, to_W, base, q), static_cast<Leg>(swing));
  return v.ok() ? "" : "swing: " + v.detail;
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

int NumVariants(const ContactPlannerConfig& config) {
  return 2 + static_cast<int>(config.base_shift.lateral_offsets_m.size() + config.base_shift.height_offsets_m.size());
}

Eigen::Vector3d BaseVariant(const ContactPlannerConfig& config, const Node& parent, int variant) {
  RBCP_CHECK(variant >= 0 && variant < NumVariants(config), "shift start " + std::to_string(variant));
  const BaseShiftConfig& bs = config.base_shift;
  if (variant == 0) return parent.shift;
  if (variant == 1) return Eigen::Vector3d::Zero();
  const std::size_t k = static_cast<std::size_t>(variant - 2);
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
    result.why = "support triangle too small";
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
      result.why = "stance feet out of reach at the step pose";
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
    result.why = "stance feet out of reach with the body shifted for the swing";
  } else {
    result.why = "CoM cannot be shifted " + FixedNumber(required) + " m inside the swing support triangle";
    result.blocking = widening_leg;
  }
  return result;
}

StepAttempt TryStep(const PlannerContext& ctx, const PathTrack& path, const Node& parent, const Node::Option& option,
                    const CrawlProfile& profile) {
  const FootholdConfig& fc = ctx.config.foothold;
  ++ctx.stats.step_attempts;
  const Leg leg = option.leg;
  const int j = Index(leg);
  const PathPose pose = path.At(option.t);
  SwingShiftResult swing = SwingShift(ctx, pose, parent, leg, BaseVariant(ctx.config, parent, option.variant));
  if (!swing.shift) return {StepOutcome::kPoseInvalid, std::move(swing.why), swing.blocking, Node{}};
  const Eigen::Vector3d shift = *swing.shift;
  const JointVector& q_pre = swing.q;
  const StanceBase& step_base = swing.base;
  const Eigen::Isometry3d& base = step_base.base_W;

  // The stance before lift-off: collision, swing triangle, torques of the three-foot stance.
  if (std::optional<StepAttempt> invalid = LiftOffFailure(ctx, parent.state, leg, step_base, q_pre)) {
    return std::move(*invalid);
  }

  // Target of the new foothold.
  PathPose target_pose;
  if (option.goal_step) {
    target_pose = path.At(path.End());
  } else {
    RBCP_CHECK(option.lead >= 0 && static_cast<std::size_t>(option.lead) < fc.lead_time_factors.size(),
               "lead index " + std::to_string(option.lead));
    const double lead = fc.lead_time_s * fc.lead_time_factors[static_cast<std::size_t>(option.lead)];
    target_pose = LeadPose(path, option.t, lead, fc.max_lead_yaw_rad);
  }
  const Eigen::Vector3d target = PathBasePose(target_pose) * ctx.robot.ReferenceFootPosition(leg);
  const Eigen::Isometry3d T_BW = base.inverse();
  const Eigen::Vector3d old_foot = parent.state.feet[static_cast<std::size_t>(j)].position;
  const std::vector<Eigen::Vector3d> stance = FeetPositions(parent.state.feet, j);
  // The pose of the look-ahead below (the path pose lead_time_s later).
  const PathPose ahead_pose = LeadPose(path, option.t, fc.lead_time_s, fc.max_lead_yaw_rad);
  int lp_evaluations = 0;
  std::vector<Eigen::Vector3d> swing_failed;  // footholds whose swing cannot keep clear
  std::size_t candidates_seen = 0;
  std::string last_reject;
  // Footholds near the target first (most steps end there, and the database query is the
  // planner's main cost), then the rest of the workspace.
  const double near_half = fc.near_query_half_m;
  for (int stage = near_half > 0.0 ? 0 : 1; stage < 2; ++stage) {
    const std::vector<Candidate> cands =
        RankedCandidates(ctx, leg, base, target, target_pose.yaw, stage == 0 ? near_half : 0.0);
    if (ctx.budget.Exhausted()) return {StepOutcome::kCapped, "time budget exhausted", std::nullopt, Node{}};
    candidates_seen += stage == 0 ? cands.size() : 0;
    for (const Candidate& c : cands) {
      if (stage == 1 && near_half > 0.0 && ((c.foothold - target).head<2>().cwiseAbs().array() < near_half).all()) {
        continue;  // evaluated in the first stage
      }
      if (stage == 1) ++candidates_seen;
      if (ctx.budget.Exhausted()) return {StepOutcome::kCapped, "time budget exhausted", std::nullopt, Node{}};
      ++ctx.stats.candidates_evaluated;
      if ((c.foothold - old_foot).norm() < fc.min_step_length_m) continue;
      if (!FarEnoughFromFeet(ctx, parent.state.feet, j, c.foothold)) continue;
      if (std::any_of(swing_failed.begin(), swing_failed.end(), [&](const Eigen::Vector3d& f) {
            return (f - c.foothold).norm() < fc.swing_failure_radius_m;
          })) {
        continue;
      }
      const Eigen::Vector3d p_B = T_BW * c.foothold;
      if (WorkspaceRatio(ctx, leg, p_B) > 1.0) {
        last_reject = "outside the workspace";
        continue;
      }
      const IkResult ik = ctx.robot.SolveLegIk(leg, p_B);
      if (!ik.ok() || !ctx.robot.KneeBent(ik.q)) {
        last_reject = "kinematics";
        continue;
      }
      JointVector q_post = q_pre;
      SetLegJoints(q_post, leg, ik.q);
      const Eigen::Vector3d com_post = CoM(ctx, base, q_post);
      if (!SupportHolds(ctx, parent.state.feet, j, com_post)) {
        last_reject = "CoM near the swing triangle edge at touch-down";
        continue;
      }
      if (ctx.stance.TerrainCollision().CheckLeg(leg, base, ik.q, true).collision) {
        last_reject = "leg collision";
        continue;
      }
      // The lift-off stance passed the whole self-collision test; only the stepping leg moved.
      if (ctx.stance.ExactCollision().CheckSelf(q_post, leg).collision) {
        last_reject = "self-collision";
        continue;
      }
      // Look-ahead: the foot must stay keepable (workspace, kinematics, no collision) at the path
      // pose lead_time_s later, so it is not placed where the advancing trunk would at once drag
      // its shank into a riser or a block edge.
      if (!option.goal_step) {
        std::array<FootContact, kNumLegs> ahead_feet = parent.state.feet;
        ahead_feet[static_cast<std::size_t>(j)].position = c.foothold;
        const Eigen::Isometry3d ahead =
            StanceBaseAt(ctx, ahead_pose, Eigen::Vector3d(0.0, 0.0, shift.z()), ahead_feet).base_W;
        if (KeepLeg(ctx, leg, ahead, c.foothold).failure != KeepFailure::kNone) {
          last_reject = "not keepable as the trunk advances";
          continue;
        }
      }
      if (lp_evaluations >= fc.max_stability_evaluations) {
        return {StepOutcome::kCapped,
                "no stable foothold among the " + std::to_string(lp_evaluations) + " best candidates (last: " +
                    last_reject + ")",
                std::nullopt, Node{}};
      }
      ++lp_evaluations;
      ++ctx.stats.stability_evaluations;
      std::array<FootContact, kNumLegs> feet = parent.state.feet;
      feet[static_cast<std::size_t>(j)].position = c.foothold;
      feet[static_cast<std::size_t>(j)].normal = ctx.surfaces[static_cast<std::size_t>(c.surface)].Normal();
      if (std::string problem = TouchDownStanceProblem(ctx, base, q_post, feet, j, com_post); !problem.empty()) {
        last_reject = std::move(problem);
        continue;
      }
      // The swing the controller will walk, from this base pose: the last test, and the dearest.
      if (std::string problem = SwingProblem(ctx, parent.state.feet, j, c.foothold, base, q_post); !problem.empty()) {
        last_reject = std::move(problem);
        swing_failed.push_back(c.foothold);
        if (static_cast<int>(swing_failed.size()) >= fc.max_swing_failures) {
          return {StepOutcome::kNoCandidate,
                  "the swings to the " + std::to_string(swing_failed.size()) + " best footholds cannot keep clear (last: " +
                      last_reject + ")",
                  std::nullopt, Node{}};
        }
        continue;
      }
      return {StepOutcome::kFound, "", std::nullopt, ChildNode(profile, parent, option, step_base, q_post, feet, shift)};
    }
  }
  if (candidates_seen == 0) last_reject = "no database sample near a contact surface";
  return {StepOutcome::kNoCandidate,
          "no valid foothold among " + std::to_string(candidates_seen) + " candidates" +
              (last_reject.empty() ? "" : " (last rejected: " + last_reject + ")"),
          std::nullopt, Node{}};
}

}  // namespace rbcp::contact_planner_detail
