#pragma once
/// What made a step of the search fail: the kind of each failure and the numbers it was found
/// with, described in words only where it is printed (Failure, the planner's reason).

#include <cstddef>
#include <optional>
#include <string>
#include <utility>

#include "rbcp/stance/stance_checker.h"

namespace rbcp::contact_planner_detail {

/// Why a foothold candidate of a step was rejected: the first test it failed.
struct CandidateFailure {
  enum class Kind {
    kWorkspace,         ///< outside the workspace box at the step's base pose
    kKinematics,        ///< no leg IK within the joint bounds, or the knee not bent
    kTouchDownSupport,  ///< the CoM near the swing triangle's edge at touch-down
    kLegCollision,      ///< the stepping leg hits the terrain
    kSelfCollision,     ///< the stepping leg hits the body
    kNotKeepable,       ///< the foot cannot be kept at the path pose lead_time_s later
    kRobustness,        ///< static equilibrium below the robustness threshold (robustness_N)
    kFourFootTorque,    ///< the four-foot stance's torques (verdict)
    kThreeFootTorque,   ///< the torques without the swing foot, not yet loaded (verdict)
    kSwing,             ///< the swing cannot keep clear (verdict)
  };

  explicit CandidateFailure(Kind kind, StanceVerdict verdict = {}) : kind(kind), verdict(std::move(verdict)) {}

  Kind kind;
  StanceVerdict verdict;      ///< the torque and swing kinds: the stance rules' verdict
  double robustness_N = 0.0;  ///< kRobustness: the robustness found [N]

  /// E.g. "outside the workspace", "robustness 2.10 N", "swing: <verdict detail>".
  std::string Describe() const;
};

/// How a step attempt ended.
enum class StepOutcome {
  kFound,        ///< a valid foothold
  kNoCandidate,  ///< every candidate failed
  kCapped,       ///< stopped early: the equilibrium-test cap or the time budget
  kPoseInvalid,  ///< no valid stance before lift-off (shift, collision, support, torques, transit)
};

/// Why a step attempt found no foothold.
struct StepFailure {
  enum class Kind {
    // The body shift for the swing (SwingShift): kPoseInvalid.
    kTriangleTooSmall,   ///< the swing's support triangle, eroded by the margins, is empty
    kStanceOutOfReach,   ///< the stance feet out of reach at the step pose
    kShiftedOutOfReach,  ///< the stance feet out of reach once the body shifts for the swing
    kCoMNotInside,       ///< the CoM cannot be shifted margin_m inside the swing triangle
    // The stance before lift-off (LiftOffFailure): kPoseInvalid.
    kLiftOffCollision,  ///< collision or self-collision before lift-off (verdict)
    kLiftOffSupport,    ///< the CoM too close to the swing triangle's edge at lift-off
    kLiftOffTorque,     ///< the three-foot stance's torques at lift-off (verdict)
    kTransit,           ///< the body's motion to the step pose (verdict)
    // The candidates: kCapped.
    kTimeBudget,     ///< the query's time budget ran out
    kStabilityCap,   ///< the first `count` candidates tested for stability were not stable
    // The candidates: kNoCandidate.
    kSwingFailures,  ///< the swings to the `count` best footholds cannot keep clear
    kNoFoothold,     ///< none of `count` candidates is valid (0: no database sample on a surface)
  };

  explicit StepFailure(Kind kind, StanceVerdict verdict = {}) : kind(kind), verdict(std::move(verdict)) {}

  Kind kind;
  StanceVerdict verdict;  ///< the lift-off kinds but kLiftOffSupport: the stance rules' verdict
  double margin_m = 0.0;  ///< kCoMNotInside: the support margin required [m]
  std::size_t count = 0;  ///< kStabilityCap, kSwingFailures, kNoFoothold
  std::optional<CandidateFailure> last;  ///< the candidate kinds: the last candidate rejected

  StepOutcome Outcome() const;
  /// The text of the reason, e.g. "no valid foothold among 12 candidates (last rejected:
  /// kinematics)", "while the body moves to the step pose: <verdict detail>".
  std::string Describe() const;
};

}  // namespace rbcp::contact_planner_detail
