#include "step_failure.h"

#include "rbcp/core/format.h"

namespace rbcp::contact_planner_detail {

std::string CandidateFailure::Describe() const {
  switch (kind) {
    case Kind::kWorkspace: return "outside the workspace";
    case Kind::kKinematics: return "kinematics";
    case Kind::kTouchDownSupport: return "CoM near the swing triangle edge at touch-down";
    case Kind::kLegCollision: return "leg collision";
    case Kind::kSelfCollision: return "self-collision";
    case Kind::kNotKeepable: return "not keepable as the trunk advances";
    case Kind::kRobustness: return "robustness " + FixedNumber(robustness_N, 2) + " N";
    case Kind::kFourFootTorque: return "four-foot stance: " + verdict.detail;
    case Kind::kThreeFootTorque: return "three-foot stance at touch-down: " + verdict.detail;
    case Kind::kSwing: return "swing: " + verdict.detail;
  }
  return "unknown candidate failure";
}

StepOutcome StepFailure::Outcome() const {
  switch (kind) {
    case Kind::kTimeBudget:
    case Kind::kStabilityCap: return StepOutcome::kCapped;
    case Kind::kSwingFailures:
    case Kind::kNoFoothold: return StepOutcome::kNoCandidate;
    default: return StepOutcome::kPoseInvalid;
  }
}

std::string StepFailure::Describe() const {
  const std::string last_text = last ? last->Describe() : "";
  switch (kind) {
    case Kind::kTriangleTooSmall: return "support triangle too small";
    case Kind::kStanceOutOfReach: return "stance feet out of reach at the step pose";
    case Kind::kShiftedOutOfReach: return "stance feet out of reach with the body shifted for the swing";
    case Kind::kCoMNotInside:
      return "CoM cannot be shifted " + FixedNumber(margin_m) + " m inside the swing support triangle";
    case Kind::kLiftOffCollision: return std::string(ToString(verdict.check)) + " before lift-off (" + verdict.detail + ")";
    case Kind::kLiftOffSupport: return "CoM too close to the swing support triangle at lift-off";
    case Kind::kLiftOffTorque: return "three-foot stance at lift-off: " + verdict.detail;
    case Kind::kTransit: return "while the body moves to the step pose: " + verdict.detail;
    case Kind::kTimeBudget: return "time budget exhausted";
    case Kind::kStabilityCap:
      return "no stable foothold among the " + std::to_string(count) + " best candidates (last: " + last_text + ")";
    case Kind::kSwingFailures:
      return "the swings to the " + std::to_string(count) + " best footholds cannot keep clear (last: " + last_text + ")";
    case Kind::kNoFoothold:
      if (count == 0) return "no valid foothold among 0 candidates (last rejected: no database sample near a contact surface)";
      return "no valid foothold among " + std::to_string(count) + " candidates" +
             (last ? " (last rejected: " + last_text + ")" : "");
  }
  return "unknown step failure";
}

}  // namespace rbcp::contact_planner_detail
