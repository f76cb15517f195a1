#pragma once
/// The robot's onboard controller: it executes a contact plan, from the measured state only
/// (RobotState) and the terrain, at the control rate: as a static crawl (ControllerConfig::mode
/// static, below) or as a dynamic walk (mode dynamic, at the end of this comment).
///
/// The plan is the contract: the contact planner checked every step as this controller walks it
/// (StanceChecker::CheckStep: the base on the plan's poses, the swing on the path StanceChecker
/// plans), so the controller chooses nothing itself. For each state i of the plan, reached from
/// state i-1 by moving leg L:
///  1. shift: with four feet down, the base moves to the state's base pose;
///  2. unload: L's share of the load ramps to zero;
///  3. swing: L's foot follows the swing path the plan carries for the step (without one, the
///     path StanceChecker::PlanSwing gives from state i-1's foothold to state i's, the base at
///     state i's pose), started where the foot is; a contact after swing.touchdown_phase is a touchdown (early if the path was not
///     finished) when it is within 2 cm of the foothold's height or pushes along its normal (at
///     least 5 N within 37 degrees of it: the terrain is higher than planned); a sideways contact
///     above the foothold, such as the face of a riser beside it, is not;
///     When the centre of pressure of the stance feet (from their measured forces) comes within
///     swing.tip_margin_m of their polygon's edge for swing.tip_hold_s, the robot tips towards the leg in the air: the
///     rest of the swing runs swing.tip_speedup times faster, on the same path;
///  4. search: a foot that reaches the end of its path without contact reaches down along the
///     normal (a late touchdown), and fails as "no ground" beyond swing.search_depth_m;
///  5. load: L's share ramps back to one; the step is done.
/// The status reports how far the measured base is from the reference it tracks.
/// After the last state the base moves to the final base pose and holds it.
///
/// Replanning (SetAwaitPlans): after each step the controller stands on its four feet, the base
/// where the step left it, and waits (kAwait) for a plan that starts from that stance
/// (ReplacePlan), or for ContinuePlan to go on with the rest of the current one. A plan that does
/// not reach the goal (ContactPlan::reaches_goal false) ends in that wait too; the last step of one
/// that does goes straight on to the final base pose.
///
/// Stance legs carry a wrench from a virtual model on the base pose (PD plus gravity), spread
/// over the feet within friction cones (DistributeWrench); their torques are -J^T f plus the
/// legs' gravity torques plus a joint PD towards the inverse kinematics of the measured feet at
/// the desired base pose (its P part fading on a foot the ground carries with less than half its
/// share of the weight, its D part on the joint rates of the base's reference motion). Swing legs
/// follow the inverse kinematics of their path under joint PD with gravity compensation. Every
/// torque is clipped at the robot's continuous torque limit
/// (RobotModel::ContinuousTorqueLimit).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <optional>
#include <string>

#include "rbcp/controller/controller_config.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/equilibrium/force_distribution.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/robot/robot_state.h"
#include "rbcp/stance/stance_checker.h"
#include "rbcp/stance/swing_trajectory.h"
#include "rbcp/stance/walking_pattern.h"

namespace rbcp {

enum class ControllerPhase {
  kHold,        ///< no plan: holds the stance it has
  kSettle,      ///< moves the base to the plan's first state
  kShift,       ///< base shift before a lift-off
  kUnload,      ///< the stepping leg's load ramps down
  kSwing,       ///< the stepping foot follows its swing path
  kSearch,      ///< the stepping foot reaches down for ground it has not found yet
  kLoad,        ///< the stepping leg's load ramps up after touchdown
  kAwait,       ///< at a step boundary, waits for the next plan (SetAwaitPlans)
  kFinalShift,  ///< after the last step: base to the final base pose
  kDone,        ///< the plan is executed; holds the final stance
  kFailed,      ///< a step cannot go on (see failure); holds the stance it has
};

const char* ToString(ControllerPhase phase);

struct ControllerStatus {
  ControllerPhase phase = ControllerPhase::kHold;
  int step = 0;                   ///< index of the plan state being walked to (0 before the first step)
  int steps_done = 0;             ///< states reached so far, not counting the first
  std::optional<Leg> swing_leg;   ///< the leg unloading, swinging, searching or reloading
  std::array<bool, kNumLegs> stance{true, true, true, true};  ///< legs pushing on the ground
  double support_margin_m = 0.0;  ///< CoM projection inside the stance feet's polygon [m]
  int early_touchdowns = 0;
  int late_touchdowns = 0;
  int hurried_swings = 0;         ///< swings sped up because the robot tipped towards the leg in the air
  std::string failure;            ///< kFailed: why
  std::optional<Leg> failure_leg;
  double base_error_m = 0.0;      ///< distance of the measured base from its reference [m]
  double step_max_base_error_m = 0.0;  ///< the largest base_error_m since the current step began [m]
  double phase_start_s = 0.0;     ///< when the current phase began [s]
  double plan_start_s = 0.0;      ///< when the current plan began [s]
  double lag_s = 0.0;             ///< dynamic walk: time the pattern's clock stood still for a late step [s]
};

/// The base pose the controller is steering to, with its rates (world frame).
struct BaseReference {
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
  Eigen::Vector3d linear_velocity_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_acceleration_W = Eigen::Vector3d::Zero();  ///< feed-forward (dynamic walk)
};

class PlanController {
 public:
  /// `robot` and `terrain` (may be null: swing paths without terrain checks) must outlive the
  /// controller; `rules` are the stance rules the planner checked the plans with. Throws
  /// InputError for an invalid config or terrain mesh.
  PlanController(const RobotModel& robot, const ControllerConfig& config, const StanceRules& rules,
                 const TriangleMesh* terrain);

  /// Executes `plan` from its first state, starting at the next Update. The robot should stand
  /// on the first state's footholds. Throws InputError for an empty plan, a state with non-finite
  /// numbers or a moving leg out of range.
  void StartPlan(const ContactPlan& plan);

  /// Replaces the rest of the current plan at the next step boundary (immediately when holding,
  /// settling or done): its first state is the stance at that boundary and its later states are
  /// executed next. Throws InputError as StartPlan.
  void ReplacePlan(const ContactPlan& plan);

  /// With `await` the controller waits at every step boundary for ReplacePlan or ContinuePlan
  /// (see the top of this file); without, it walks each plan through (the default).
  void SetAwaitPlans(bool await) { await_plans_ = await; }
  /// At a step boundary (kAwait): go on with the rest of the current plan at the next Update. A
  /// plan that does not reach the goal and has no step left keeps waiting. No effect elsewhere.
  void ContinuePlan();

  /// The terrain of the swing paths (may be null).
  void SetTerrain(const TriangleMesh* terrain);

  /// One control tick: joint torque commands [N m] for the measured state.
  JointVector Update(const RobotState& state);

  const ControllerStatus& Status() const { return status_; }
  const BaseReference& Reference() const { return reference_; }
  /// The plan being executed (empty before StartPlan).
  const ContactPlan& Plan() const { return plan_; }
  const ControllerConfig& Config() const { return config_; }
  /// The stance rules it walks by, with the terrain of its swing paths.
  const StanceChecker& Stance() const { return stance_; }
  /// Dynamic walk: the walking pattern of the plan being walked, and the time on its clock
  /// (null in the static crawl, before a plan and after a failure).
  const WalkingPattern* Pattern() const { return pattern_ ? &*pattern_ : nullptr; }
  double PatternTime() const { return pattern_time_s_; }
  /// Where the swinging foot is to be now (world frame), during a swing or a search.
  const Eigen::Vector3d& SwingTarget() const { return swing_target_W_; }
  /// Dynamic walk: the steps after the current one (the step being walked, or at a boundary the
  /// next) whose lift-off lies within the ZMP preview of the current step's end. The CoM's motion
  /// already prepares for their support, so a plan that replaces this one should keep them. 0 in
  /// the static crawl, and without a step ahead.
  int CommittedSteps() const;

 private:
  struct BaseSegment {
    double t0 = 0.0;
    double duration = 1.0;
    Eigen::Vector3d p0 = Eigen::Vector3d::Zero(), p1 = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity(), q1 = Eigen::Quaterniond::Identity();
    bool Done(double t) const { return t >= t0 + duration; }
  };
  struct Measured;

  void Enter(ControllerPhase phase, double t);
  bool OnFoothold(const Measured& m, std::size_t leg) const;
  /// Moves through the phases the measured state ends this tick.
  void Advance(const Measured& m);
  /// Starts the plan StartPlan took: the base settles onto its first state.
  void BeginPlan(const Measured& m);
  /// One phase's transition, if its end condition holds.
  void AdvancePhase(const Measured& m);
  /// The swing leg `sl` unloads over unload_s, then lifts off on its swing path.
  void AdvanceUnload(const Measured& m, std::size_t sl, double elapsed);
  /// Touchdown on the foothold late enough in the swing; at the swing's end, the search.
  void AdvanceSwing(const Measured& m, std::size_t sl);
  /// The centre of pressure of the stance feet's measured forces along their normals.
  CentreOfPressure StanceCentreOfPressure(const Measured& m) const;
  /// The centre of pressure of the stance feet within swing.tip_margin_m of their polygon's edge.
  bool Tipping(const Measured& m) const;
  /// The centre of pressure of the stance feet's measured forces at least swing.tip_margin_m
  /// inside the polygon of the stance feet but `leg` (true when there is nothing to go by).
  bool CarriedWithout(const Measured& m, std::size_t leg) const;
  /// The legs' load ramps (the stance library's walk: one clock for planner and controller).
  const GaitPhases& Ramps() const { return stance_.Config().dynamic_walk.gait; }
  /// Time along the swing path at time t: the time since lift-off, faster once hurried.
  double SwingTime(double t) const;
  /// The foot reaches down along the foothold's normal until it touches down, or fails.
  void AdvanceSearch(const Measured& m, std::size_t sl, double elapsed);
  /// Leg `sl` is a stance leg again, to be loaded, with its foothold's normal.
  void TouchDown(std::size_t sl, double t);
  /// A new plan, or the go-ahead to walk on, ends the wait.
  void AdvanceAwait(const Measured& m);
  void BeginStep(int index, const Measured& m);
  void FinishStep(const Measured& m);
  void NextStepOrFinish(const Measured& m);  // the current plan's next step, else the final shift or the wait
  void BeginFinalShift(const Measured& m);
  void Fail(const Measured& m, Leg leg, const std::string& why);
  void MoveBaseTo(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double t, double min_duration);
  /// The base's min-jerk segment to (p, q), over exactly `duration`.
  void MoveBaseOver(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double t, double duration);
  bool Dynamic() const { return config_.mode == WalkMode::kDynamic; }
  /// Dynamic walk: the pattern of the current plan, from the pattern's CoM where one is being
  /// walked, else from the measured CoM at rest.
  /// `come_to_rest`: the CoM's motion is for a step the new plan does not take (PatternStart).
  void StartPattern(const Measured& m, bool come_to_rest = false);
  /// Dynamic walk: the pattern's clock follows the tick, up to the current step's swing end
  /// until its touchdown.
  void AdvanceClock(const Measured& m);
  /// Dynamic walk: a leg that touched down loads over load_s.
  void RampLoads(const Measured& m);
  /// The plan ReplacePlan left pending becomes the current one.
  void TakePendingPlan(const Measured& m);
  /// The swing path of plan state `index`'s step, started at the measured foot foot_W.
  SwingTrajectory PlanSwing(int index, const Eigen::Vector3d& foot_W) const;
  void EvaluateReference(double t);
  JointVector Torques(const Measured& m);
  /// The wrench on the trunk about the CoM that holds the base on its reference.
  Wrench BaseWrench(const Measured& m) const;
  /// The wrench distributed over the loaded stance feet; sets the status's support margin.
  ForceDistribution StanceForces(const Measured& m, const Wrench& wrench);
  /// Adds to the stance leg's torques `t` its share of the wrench (force_W at its foot) and the
  /// joint servo that keeps its foot in place.
  void AddStanceTorques(const Measured& m, Leg leg, const Eigen::Matrix3d& J, const Eigen::Vector3d& force_W,
                        Eigen::Vector3d& t) const;
  /// Adds to the swinging (or searching) leg's torques `t` the joint PD that follows its path.
  void AddSwingTorques(const Measured& m, Leg leg, const Eigen::Matrix3d& J, Eigen::Vector3d& t);
  static void CheckPlan(const ContactPlan& plan);

  const RobotModel& robot_;
  ControllerConfig config_;
  StanceChecker stance_;

  ContactPlan plan_;
  std::optional<ContactPlan> pending_;
  bool started_ = false;      // the first Update has run
  bool plan_started_ = false; // StartPlan was called and the plan not begun yet
  bool await_plans_ = false;
  bool continue_requested_ = false;
  ControllerStatus status_;
  BaseSegment segment_;
  BaseReference reference_;
  std::array<double, kNumLegs> load_{1.0, 1.0, 1.0, 1.0};
  std::array<Eigen::Vector3d, kNumLegs> normal_W_;
  SwingTrajectory swing_;
  Eigen::Vector3d swing_target_W_ = Eigen::Vector3d::Zero();  // current point of the swing or search
  Eigen::Vector3d swing_velocity_W_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d search_start_W_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d swing_q_des_ = Eigen::Vector3d::Zero();
  std::optional<double> swing_hurried_at_;  // when the robot tipped during this swing
  std::optional<double> tipping_since_;     // since when the centre of pressure is at the edge
  double unload_began_s_ = 0.0;             // when the current step's leg began to unload
  // Dynamic walk.
  std::optional<WalkingPattern> pattern_;
  double pattern_time_s_ = 0.0;  // on the pattern's clock
  bool clock_held_ = false;      // the clock stood still this tick
  double last_tick_s_ = 0.0;
  std::array<double, kNumLegs> touchdown_s_;  // when a loading leg touched down (NaN: loaded or swinging)
};

}  // namespace rbcp
