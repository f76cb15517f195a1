#pragma once
/// A contact plan walked in the simulated world by the onboard controller, and judged by the
/// simulator from the true world (never from what the controller believes).
///
/// Outcome: the goal is reached when the controller has executed every state, the base is within
/// outcome.goal_tolerance_m of the plan's final base and the four feet stand on the terrain. The
/// first failure ends the run:
///  - "fall": the trunk or a thigh touches the terrain, or roll or pitch leaves the plan's by more
///    than outcome.max_tilt_rad;
///  - "foot_slip": a foot in contact moves more than outcome.max_slip_m from where it touched down;
///  - "torque_saturation": a joint's command stays at the torque limit longer than
///    outcome.max_saturation_s;
///  - "no_ground": the controller reached down for a foothold and the foot touches nothing;
///  - "controller": the controller stopped for another reason;
///  - "timeout": the run outlasts timeout_base_s + timeout_per_step_s per step;
///  - "no_plan": the planners gave up on the robot's stance (Abort).
/// Other robot-terrain contacts (hips, shanks, foot adapters) are counted as collisions. A failure
/// names the stance check that should have caught it (ExecutionFailure::should_have_caught).

#include <Eigen/Core>
#include <array>
#include <limits>
#include <map>
#include <ostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "rbcp/controller/plan_controller.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/sim/bullet_world.h"
#include "rbcp/sim/sim_config.h"

namespace rbcp::sim {

struct ExecutionFailure {
  std::string what;    ///< "fall", "foot_slip", "torque_saturation", "no_ground", "controller", "timeout",
                       ///< "short_of_goal" (JudgeAgainstGoal)
  double t = 0.0;      ///< simulated time [s]
  int step = 0;        ///< plan state being walked to
  std::string leg;     ///< leg or joint concerned ("LF", "RH_KFE", "" when none)
  std::string phase;   ///< what the controller was doing ("swing", "shift", ...; see ControllerPhase)
  std::string detail;  ///< what was seen, with numbers
  /// The stance check that should have caught it (StanceChecker, "<phase>: <check>"), and, where
  /// the plan's step fails that check on the world as it is, the verdict: e.g. "swing: swing_body
  /// (the swinging leg held)", "shift: torque; the step fails it: shift: torque: ...". Empty for
  /// failures no stance check is about (timeout, no_plan).
  std::string should_have_caught;
};

/// The robot at one instant of a run (the 20 Hz trace of a simulated run or of a run's log).
struct TraceSample {
  double t = 0.0;
  Eigen::Vector3d base_position = Eigen::Vector3d::Zero();  ///< [m], world
  Eigen::Vector3d base_rpy = Eigen::Vector3d::Zero();       ///< [rad]
  std::array<Eigen::Vector3d, kNumLegs> feet;               ///< each foot's contact point [m], world
  std::array<bool, kNumLegs> contact{};
  JointVector joints = JointVector::Zero();   ///< measured joint positions [rad]
  JointVector torques = JointVector::Zero();  ///< applied joint torques [N m]
  /// Signed distance [m] from the CoM's ground projection to the edge of the polygon of the feet
  /// in contact (positive inside); NaN with fewer than three feet in contact.
  double support_margin_m = std::numeric_limits<double>::quiet_NaN();
  int step = -1;      ///< plan state the controller walks to (-1: unknown)
  std::string phase;  ///< the controller's phase ("" unknown; see ControllerPhase)
  /// Dynamic walk: the CoM [m] (x, y) the controller steers to and the ZMP reference of its
  /// walking pattern at this instant; NaN in the static crawl or when unknown.
  Eigen::Vector2d com_reference = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector2d zmp_reference = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// The centre of pressure [m] (x, y) of the measured vertical foot forces (CentreOfPressure).
  Eigen::Vector2d cop = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// The centre of pressure (ComputeCentreOfPressure) of the measured vertical (world z) foot forces
/// over the feet in contact, the feet at the forward kinematics of the measured joints.
CentreOfPressure MeasuredCentreOfPressure(const RobotModel& robot, const RobotState& state);

/// A trace sample of a measured state: the feet at the forward kinematics of the measured joints,
/// the support margin of the whole-body CoM over the feet in contact, the centre of pressure.
TraceSample MeasuredTraceSample(const RobotModel& robot, const RobotState& state);

/// {t, base: {position, rpy}, feet: [{leg, position, contact}], joints, torques, support_margin_m,
/// com_reference, zmp_reference and cop (each null when NaN), step and phase (when known)}; joints
/// rounded to 1e-5 rad, torques to 1e-3 N m.
nlohmann::json TraceSampleToJson(const TraceSample& sample);

struct ExecutionOutcome {
  bool reached_goal = false;
  std::optional<ExecutionFailure> failure;
  double sim_time_s = 0.0;
  int steps_total = 0;      ///< steps of the plan (states after the first)
  int steps_executed = 0;
  double max_torque_ratio = 0.0;  ///< largest |applied torque| / limit
  int collisions = 0;             ///< onsets of other robot-terrain contacts
  std::map<std::string, int> collision_links;  ///< the same by link
  int early_touchdowns = 0;
  int late_touchdowns = 0;
  double final_base_error_m = 0.0;  ///< base distance to the plan's final base at the end
  double min_support_margin_m = std::numeric_limits<double>::infinity();  ///< least CoM margin in the stance polygon during swings
  double max_slip_m = 0.0;  ///< farthest a stance foot's contact point slid along the terrain since its touchdown [m]
  std::vector<TraceSample> trace;
  bool fell() const { return failure && failure->what == "fall"; }
  bool ok() const { return reached_goal && !failure; }
};

/// A run of a whole plan judged against the scenario's goal too: walked whole (outcome.ok()) but
/// ending farther than tolerance_m (horizontally) from `goal`, the goal is not reached; the
/// outcome then fails as "short_of_goal" with the distance. A plan of one state, walked at once,
/// reaches the goal only where it stands on it.
void JudgeAgainstGoal(ExecutionOutcome& outcome, const ContactPlan& plan, const BaseGoal& goal, double tolerance_m);

class PlanExecution {
 public:
  /// Builds the world of `scenario` (its terrain: the world may differ from the one the plan was
  /// made on) and a controller that knows that terrain and walks by `stance_rules` (those the
  /// plans were checked with). The models must outlive this object.
  PlanExecution(const RobotModel& robot, const Scenario& scenario, const SimConfig& sim_config,
                const ControllerConfig& controller_config, const StanceRules& stance_rules);
  ~PlanExecution();

  /// Puts the robot at rest in the plan's first state (lifted by drop_height_m over the terrain)
  /// and hands the plan to the controller.
  void Start(const ContactPlan& plan);
  /// Puts the robot at rest in the reference stance at `pose` on the terrain, with no plan: the
  /// controller holds it until StartPlan.
  void StandAt(const BaseGoal& pose);
  /// Hands a plan to the controller (replacing the rest of a running one at a step boundary).
  /// Throws InputError for a plan of more than kMaxPlanSteps steps.
  void GivePlan(const ContactPlan& plan);
  /// The most steps of a plan the simulator walks (about 100 m of rough terrain).
  static constexpr std::size_t kMaxPlanSteps = 2000;
  /// Replanning: the controller waits at every step boundary for the next plan (GivePlan) or for
  /// ContinuePlan (PlanController::SetAwaitPlans). Time spent waiting does not count towards the
  /// run's timeout.
  void SetAwaitPlans(bool await);
  /// True while the controller waits for a plan: at a step boundary, or standing with none yet.
  bool Awaiting() const;
  /// At a step boundary: go on with the rest of the current plan.
  void ContinuePlan() { controller_->ContinuePlan(); }
  /// Ends the run undecided so far with the failure `what` ("no_plan") and `detail`.
  void Abort(const std::string& what, const std::string& detail);
  /// Whether ContinuePlan has something to walk: a step left, or the final pose of a plan that
  /// reaches the goal.
  bool CanContinue() const;

  /// The world changes while the robot walks (a box added or removed): the simulated terrain, the
  /// one the judge measures against and the one the controller plans its swings over. Throws
  /// InputError for an invalid element (nothing changes then).
  void SetTerrain(std::vector<TerrainElement> terrain);
  /// The world as it is now: the scenario with its current terrain.
  const Scenario& CurrentWorld() const { return scenario_; }
  /// An external force on the base [N], world frame, until changed (a push).
  void SetBaseForce(const Eigen::Vector3d& force_W) { world_->SetBaseForce(force_W); }

  /// One control period: the controller's torques from the measured state, then the physics
  /// steps of that period, then the judge. Returns false once the outcome is decided.
  bool Tick();
  /// Ticks until the outcome is decided.
  const ExecutionOutcome& Run();

  bool Decided() const { return decided_; }
  const ExecutionOutcome& Outcome() const { return outcome_; }
  RobotState State() const { return world_->State(); }
  BulletWorld& World() { return *world_; }
  const PlanController& Controller() const { return *controller_; }
  const RobotModel& Robot() const { return robot_; }
  double Time() const { return world_->Time(); }

 private:
  void Reset(const Eigen::Vector3d& base_W, const Eigen::Quaterniond& orientation_W, const JointVector& q);
  /// Records the tick's maxima and decides the outcome when the run failed or ended this tick.
  void Judge(const RobotState& state, const JointVector& commanded);
  /// The trunk or a thigh on the terrain (a fall); counts the other links that start touching it.
  std::optional<ExecutionFailure> BodyContactFailure(const std::vector<TerrainContact>& contacts);
  /// Roll or pitch more than max_tilt_rad from the plan's states on either side of the step.
  std::optional<ExecutionFailure> TiltFailure(const RobotState& state, const ControllerStatus& status) const;
  /// A stance foot that slid more than max_slip_m from where it touched down.
  std::optional<ExecutionFailure> SlipFailure(const RobotState& state, const ControllerStatus& status,
                                              const std::vector<TerrainContact>& contacts);
  /// A joint commanded at the torque limit for longer than max_saturation_s.
  std::optional<ExecutionFailure> SaturationFailure(double t, const JointVector& commanded);
  /// The end of the run: the controller stopped, walked the whole plan, or the time ran out.
  void JudgeEnd(const RobotState& state, const ControllerStatus& status);
  void Decide(std::optional<ExecutionFailure> failure);
  /// A failure at the current time, step and phase.
  ExecutionFailure Failure(const std::string& what, const std::string& leg, const std::string& detail) const;
  /// ExecutionFailure::should_have_caught of `failure`, from the controller's phase and step.
  std::string ShouldHaveCaught(const ExecutionFailure& failure) const;
  void Sample(const RobotState& state);

  const RobotModel& robot_;
  SimConfig config_;
  Scenario scenario_;
  std::unique_ptr<BulletWorld> world_;
  std::unique_ptr<PlanController> controller_;
  ContactPlan plan_;
  bool has_plan_ = false;
  bool await_plans_ = false;
  bool decided_ = false;
  ExecutionOutcome outcome_;
  double timeout_s_ = 0.0;
  double next_sample_s_ = 0.0;
  // Per stance foot since its touchdown: the sphere's frame at the last tick and the distance its
  // contact point slid along the terrain (the centre's motion less the sphere's rolling).
  std::array<std::optional<Eigen::Isometry3d>, kNumLegs> foot_frame_W_;
  std::array<Eigen::Vector3d, kNumLegs> slide_W_;
  std::array<double, kNumLegs> last_contact_s_{};
  std::array<double, kNumJoints> saturated_since_{};
  std::map<std::string, bool> touching_;  // links other than feet touching the terrain now
};

/// The outcome as JSON: sim_ok, reached_goal, fell, sim_time_s, failure (null or {what, t, step,
/// leg, phase, detail, should_have_caught}), max_torque_ratio, collisions, collision_links, steps_total, steps_executed,
/// early_touchdowns, late_touchdowns, final_base_error_m, min_support_margin_m, max_slip_m and sim_trace
/// (TraceSampleToJson; docs/json_schema.md).
nlohmann::json OutcomeToJson(const ExecutionOutcome& outcome);

/// A control-rate record of a run for diagnosis, one CSV row per tick: t, the controller's phase,
/// step, swing leg and support margin, the base position and roll-pitch-yaw with the reference
/// position, the 12 joint positions and applied torques (named as in the URDF), per foot the
/// contact flag and the normal (world z) contact force, the centre of pressure of the foot
/// forces (x, y) with its distance inside the polygon of the feet in contact, and the dynamic
/// walk's lag.
void WriteTickCsvHeader(std::ostream& out);
void WriteTickCsvRow(std::ostream& out, const PlanExecution& execution);

}  // namespace rbcp::sim
