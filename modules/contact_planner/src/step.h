#pragma once
/// One step of the search: the body shift for the swing, the stance at lift-off, and the new
/// foothold (the first database candidate that passes every test).

#include <Eigen/Core>
#include <optional>

#include "path_track.h"
#include "planner_context.h"
#include "rbcp/robot/robot_model.h"
#include "search_node.h"
#include "stance_checks.h"
#include "step_failure.h"

namespace rbcp::contact_planner_detail {

/// The starts of the shift search a step option may take, by index: 0 the parent's shift (the
/// body stays where it is); 1 the path pose; then the lateral offsets; then the height offsets
/// (path heading frame, z = height added to the stance height).
int NumShiftStarts(const ContactPlannerConfig& config);
Eigen::Vector3d ShiftStart(const ContactPlannerConfig& config, const Node& parent, int shift_start);

/// The body shift of a swing, or why there is none.
struct SwingShiftResult {
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();  ///< path heading frame (when ok)
  StanceBase base;                                  ///< the base pose at the shift (when ok)
  JointVector q = JointVector::Zero();              ///< the stance's joints with the base at the shift (when ok)
  std::optional<StepFailure> failure;               ///< why the margin cannot be met; nullopt when ok
  /// The stance leg whose re-placement would widen a support triangle the CoM cannot get into.
  std::optional<Leg> blocking;
  bool ok() const { return !failure; }
};

/// Shift (path heading frame) that puts the CoM support_margin + extra inside the triangle of
/// the stance feet (all of parent's but `swing`), with the base at path pose `pose`, searched from
/// `start` (horizontal offset and height offset). Each update moves the CoM toward the eroded
/// triangle; an update that puts a stance foot out of reach is halved until the stance is
/// reachable.
SwingShiftResult SwingShift(const PlannerContext& ctx, const PathPose& pose, const Node& parent, Leg swing,
                            const Eigen::Vector3d& start);

/// What one step attempt came to.
struct StepAttempt {
  std::optional<StepFailure> failure;  ///< what failed; nullopt when a foothold was found
  /// A stance leg to re-place first: it hits the terrain when the body shifts for this swing,
  /// or its re-placement widens a swing triangle the CoM cannot get into.
  std::optional<Leg> blocking;
  Node child;  ///< the node after the step, when found
  StepOutcome outcome() const { return failure ? failure->Outcome() : StepOutcome::kFound; }
};

/// Why the stance before `leg` lifts off from `from`'s feet, with the base at `base` and the
/// joints q_pre, is invalid (kPoseInvalid): collision (a stance leg that hits the terrain is
/// named as blocking), self-collision, the swing triangle, the torques of the three-foot stance,
/// or the transit from `from`'s base; nullopt when it is valid.
std::optional<StepAttempt> LiftOffFailure(const PlannerContext& ctx, const WholeBodyState& from, Leg leg,
                                          const StanceBase& base, const JointVector& q_pre);

/// Why the stance on `feet` just after `swing` touches down, with the base at `base`, joints q
/// and the CoM at com_W, is invalid: static equilibrium below the robustness threshold, or the
/// torques of the four-foot stance or of the three-foot stance without `swing` (its foot not yet
/// loaded); nullopt when it is valid.
std::optional<CandidateFailure> TouchDownStanceFailure(const PlannerContext& ctx, const Eigen::Isometry3d& base,
                                                       const JointVector& q, const Feet& feet, int swing,
                                                       const Eigen::Vector3d& com_W);

/// Why the swing of leg `swing` from its foothold in from_feet to to_W, with the base held at
/// `base` and the other legs at q, cannot keep clear of the terrain (or of the body): the path
/// the controller walks (StanceChecker::PlanSwing); nullopt when it can.
std::optional<CandidateFailure> SwingClearanceFailure(const PlannerContext& ctx, const Feet& from_feet, int swing,
                                                      const Eigen::Vector3d& to_W, const Eigen::Isometry3d& base,
                                                      const JointVector& q);

/// Writes into every state after the first the swing path that reaches it (its apex and bow, as
/// SwingClearanceFailure found it clear), so the controller walks the path checked here; the first state
/// gets none.
void AttachSwings(const PlannerContext& ctx, std::vector<WholeBodyState>& states);

/// Steps option.leg at path time option.t from `parent`: the body shift (searched from the
/// option's shift start), the lift-off stance and the transit to it, then the database candidates
/// toward the target (the reference foot at the option's lead pose, or at the path end for a goal
/// step), nearest first, until one passes kinematics, support, collision, the look-ahead,
/// equilibrium, torques and the swing.
StepAttempt TryStep(const PlannerContext& ctx, const PathTrack& path, const Node& parent, const Node::Option& option,
                    const CrawlProfile& profile);

}  // namespace rbcp::contact_planner_detail
