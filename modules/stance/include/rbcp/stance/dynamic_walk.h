#pragma once
/// The dynamic walk of a contact plan (the controller's mode dynamic), shared by the contact
/// planner, which times every step of a plan and checks the walk that timing implies, and by the
/// controller, which walks it on that clock.
///
/// A step of the dynamic walk, from the previous state's touch-down to its own:
///  - four feet down: the base's height and attitude move (min-jerk) from the previous state's
///    pose to the step's, while the CoM follows the walking pattern (walking_pattern.h);
///  - swing: the moving leg follows its swing path (DynamicSwing) with the base at the step's
///    height and attitude, the CoM still on its pattern, over the other three feet.
/// The base's x and y are wherever the pattern puts the CoM. CheckDynamicStep checks a step at
/// poses sampled along that motion; CheckStep (stance_checker.h) checks the plan's own poses.

#include <limits>
#include <optional>
#include <vector>

#include "rbcp/core/contact_plan.h"
#include "rbcp/stance/stance_checker.h"
#include "rbcp/stance/walking_pattern.h"

namespace rbcp {

/// The swing of plan state `index`'s moving leg as the dynamic walk walks it: the plan's path
/// (without one, the path the stance rules plan from the same footholds with the base at the
/// state's pose) at the dynamic walk's swing speed; a timed step's lasts the plan's time, or
/// longer if the path needs more at that speed. `start_W`: where the foot really is when it
/// lifts (a few millimetres off its foothold), the path's start; none: the foothold.
SwingTrajectory DynamicSwing(const StanceChecker& checker, const ContactPlan& plan, int index,
                             const std::optional<Eigen::Vector3d>& start_W = std::nullopt);

/// Where the dynamic walk of `plan` starts when the robot stands still: its CoM at rest over the
/// first state's.
PatternStart DynamicWalkAtRest(const StanceChecker& checker, const ContactPlan& plan);

/// The walking pattern of `plan` from `start`: the pendulum at the height of the first state's
/// CoM above the mean height of its feet; every swing DynamicSwing's; the ZMP of a swing nearest
/// the CoM of the step's plan pose (start.step_com is set here); for a timed plan, the durations
/// of its swings and four-foot phases (ContactPlan::Timed). Throws InputError as
/// PlanWalkingPattern does.
WalkingPattern DynamicWalkPattern(const StanceChecker& checker, const ContactPlan& plan, PatternStart start);

/// How a step of the dynamic walk fares along its pattern.
struct DynamicStepCheck {
  /// The first failure: phase kShift with four feet down, kSwing with three; its leg the one out
  /// of reach or on the terrain, where one is.
  StanceVerdict verdict;
  double time_s = std::numeric_limits<double>::quiet_NaN();  ///< pattern time of that failure [s]
  /// Least distance of the pattern's ZMP inside the support polygon over the step [m].
  double min_zmp_margin_m = std::numeric_limits<double>::infinity();
  /// Largest stance joint torque over the step, the CoM accelerating as the pattern has it [N m].
  double max_torque_Nm = 0.0;
  /// Times TimeDynamicWalk slowed the step (its phases last 1.5 to the power of this longer).
  int slowdowns = 0;
};

/// Checks step `index` (1..n) of `plan` along `pattern` (DynamicWalkPattern's), every 40 ms from
/// the previous touch-down to the step's own: the pattern's ZMP inside the support polygon; every
/// stance foot in reach; the trunk and the stance legs clear of the terrain, and the swinging leg
/// once its foot is 2 cm off the ground (with a terrain, and the stance rules' clearances); the
/// stance torques, the feet pushing the CoM along its acceleration, below the ceiling.
DynamicStepCheck CheckDynamicStep(const StanceChecker& checker, const ContactPlan& plan, const WalkingPattern& pattern,
                                  int index);

/// Times every step of `plan` (at least two states) for the dynamic walk from rest and checks
/// the walk: a step whose check fails on torque, balance or support is slowed (its swing and
/// four-foot phase 1.5 times longer, at most three times), since a slower CoM accelerates less;
/// a step no slower pace cures keeps its own pace. The first `keep_steps` steps keep the
/// durations of their swings and of the four-foot phases between them from the plan's timing
/// (which they must have): steps a walk already prepares for. Writes each step's lift-off and
/// touch-down into the plan; returns every step's check at its final timing (a step may still
/// fail: reach and collisions do not depend on the pace). Throws InputError for a kept step
/// without timing.
std::vector<DynamicStepCheck> TimeDynamicWalk(const StanceChecker& checker, ContactPlan* plan, int keep_steps = 0);

}  // namespace rbcp
