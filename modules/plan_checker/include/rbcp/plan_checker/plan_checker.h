#pragma once
/// An independent check of a contact plan against its scenario: it recomputes everything from
/// the plan's states (base pose, joints, feet) with the robot model, the terrain, the contact
/// surfaces, the static-equilibrium LPs and the collision checker, and trusts nothing the
/// planner may have computed.
///
/// Checks, by name (PlanViolation::check), for state i:
///  - "surface": every foot lies on a contact surface: within surface_tolerance of its plane,
///    within surface_tolerance of its polygon in the plane, and its normal within
///    normal_tolerance of the surface normal.
///  - "one_leg": the first state has no moving leg; for i > 0 exactly one foot changes its
///    contact from state i-1 (moves by more than contact_change_tolerance or changes its normal),
///    and it is the state's moving_leg.
///  - "joint_bounds": the joints lie within the planning bounds; for i > 0 the swing leg can also
///    still reach its old foothold (inverse kinematics within the bounds) with the trunk at the
///    pose of state i (see "support_margin").
///  - "kinematic_margin": every foot lies within the robot's max_stance_hip_distance of its hip
///    (HAA origin) with its knee bent at least min_knee_bend (RobotModel::Margins); at lift-off
///    (trunk at the pose of state i) the swing foot on its old foothold within
///    max_lift_off_hip_distance, its knee bent as much.
///  - "fk": forward kinematics of the joints at the base pose puts every foot contact point on the
///    state's foot position within fk_tolerance.
///  - "collision": no robot shape touches the terrain; the four feet stand on it and may sink in
///    by the collision checker's foot tolerance.
///  - "self_collision": no two robot shapes collide.
///  - "stability": the robustness of static equilibrium on the four contacts at the whole-body
///    CoM is at least robustness_threshold_N.
///  - "torque": the joint torques that hold the robot still, with its weight spread over the four
///    feet as the controller spreads it (ComputeStanceTorques: least squares within the friction
///    pyramids, at least min_normal_force_N per foot, the legs' own weight included), stay within
///    torque_limit_Nm; so do those of the three-foot stance at lift-off (see "support_margin").
///  - "support_margin": a step from state i-1 to state i is executed as: the trunk moves from
///    the pose of state i-1 to the pose of state i with the four feet on the ground, then
///    moving_leg swings from its old foothold to its new one. The CoM's ground projection must
///    lie support_margin_m inside the support polygon of the three stance feet both at lift-off
///    (trunk at pose i, swing leg still on its old foothold) and at touchdown (state i).
///  - "shift": while the trunk moves in a straight line (position and yaw) from the pose of state
///    i-1 to that of state i on state i-1's four feet, at shift_checks poses in between: every
///    foot within reach (joint bounds), the CoM support_margin_m inside the four feet's polygon,
///    no robot shape on the terrain, the torques within torque_limit_Nm.
///  - "swing": the path the moving leg's foot follows, with the trunk at the pose of state i (the
///    swing the state carries, else the one the stance rules plan), at the points its leg is
///    planned clear at (SwingTrajectory::LegCheckPoints: once the foot is 2 cm off its
///    footholds): the foot within reach, no shape of the leg on the terrain (the foot sphere with a
///    stance foot's tolerance: the path keeps it swing.terrain_clearance_m above the terrain over
///    its middle), none on the trunk or another leg.
///  - "timing" (state 0): the steps' lift-off and touch-down times are consistent (TimingProblem).
///
/// A timed plan (ContactPlan::Timed) is also checked along the dynamic walk its timing implies,
/// from rest (CheckDynamicStep, stance/dynamic_walk.h): at poses every 40 ms from the previous
/// touch-down to the step's own, the ZMP inside the support polygon, every stance foot in reach,
/// the trunk and the stance legs clear of the terrain (with the stance rules' clearances), the
/// stance torques with the CoM's acceleration within the stance rules' ceiling. Its findings
/// ("walk") are reported apart: the plan's verdict is about its own states and steps.

#include <nlohmann/json_fwd.hpp>

#include <limits>
#include <string>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/equilibrium/config.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/stance/stance_config.h"

namespace rbcp {

/// Tolerances and limits of the plan checker.
struct PlanCheckConfig {
  /// A foot is on a surface when it is within this distance of the surface plane and within it
  /// of the polygon in the plane [m].
  double surface_tolerance = 1e-3;
  /// Largest norm of the difference between a foot's normal and its surface's normal [-].
  double normal_tolerance = 1e-3;
  /// Largest distance between a foot position and the forward kinematics of the joints [m].
  double fk_tolerance = 1e-4;
  /// A foot that moves further than this between two states changes its contact [m].
  double contact_change_tolerance = 1e-3;
  /// Minimum robustness of static equilibrium on the four feet [N].
  double robustness_threshold_N = std::numeric_limits<double>::quiet_NaN();
  /// Minimum distance of the CoM's ground projection inside the stance triangle of a swing [m].
  double support_margin_m = std::numeric_limits<double>::quiet_NaN();
  /// Largest static joint torque [N m].
  double torque_limit_Nm = std::numeric_limits<double>::quiet_NaN();
  /// Least normal force of a stance foot in the torque check's force distribution [N] (the stance
  /// rules' min_normal_force_N).
  double min_normal_force_N = 15.0;
  /// Friction cone model of the stability and torque checks (friction, generators per contact,
  /// normal force slack). Its thresholds are not used: the two fields above are.
  EquilibriumConfig equilibrium;
  /// Terrain and self collision are checked only when set (the swing check needs them).
  bool check_collision = true;
  /// Trunk poses checked during a shift [-], >= 1.
  int shift_checks = 6;
  /// The stance rules, for the swing path of a state that carries none.
  StanceRules stance;
  /// At most this many violations are kept in the report; all are counted.
  int max_violations = 100;

  /// The thresholds of the planners: robustness from `equilibrium`, support margin and least
  /// normal force from the stance rules, the actuators' command torque limit
  /// (RobotModel::ContinuousTorqueLimit), the default tolerances above.
  static PlanCheckConfig FromConfigs(const RobotModel& robot, const EquilibriumConfig& equilibrium,
                                     const StanceRules& stance);

  /// Throws InputError naming the first missing or out-of-range field ("PlanCheckConfig:
  /// 'torque_limit_Nm': expected a finite value > 0, got nan").
  void Validate() const;
};

/// One failed check.
struct PlanViolation {
  int state = 0;       ///< index of the state in the plan
  std::string check;   ///< "surface", "one_leg", "joint_bounds", "fk", "collision", "self_collision",
                       ///< "stability", "torque" or "support_margin"
  std::string detail;  ///< what was found, with the numbers and the limit
};

struct PlanCheckReport {
  bool ok = false;                          ///< no violation
  std::vector<PlanViolation> violations;    ///< by state, then in the order of the checks above;
                                            ///< at most PlanCheckConfig::max_violations
  int violation_count = 0;                  ///< all violations found, including those not kept
  int states = 0;                           ///< states checked
  /// Smallest robustness over the states [N] (+infinity for a plan without states; -infinity
  /// when a stance cannot balance gravity at all).
  double min_robustness_N = std::numeric_limits<double>::infinity();
  /// Largest absolute static joint torque over the states whose forces could be distributed [N m].
  double max_torque_Nm = 0.0;
  /// Smallest CoM margin in a stance triangle over all swings [m] (+infinity without a swing).
  double min_support_margin_m = std::numeric_limits<double>::infinity();
  /// The plan carries its steps' timing, and its dynamic walk was checked.
  bool timed = false;
  /// The steps whose dynamic walk fails a check (check "walk", detail CheckDynamicStep's verdict).
  std::vector<PlanViolation> walk_violations;
  /// Of a timed plan's walk: the least margin of its ZMP inside the support polygon [m] and the
  /// largest stance torque with the CoM's acceleration [N m].
  double min_zmp_margin_m = std::numeric_limits<double>::infinity();
  double max_walk_torque_Nm = 0.0;

  /// One line: "plan passes: 9 states, min robustness 14.2 N, ..." or "plan fails: 3
  /// violations in 9 states (stability, torque); ...".
  std::string Summary() const;
};

/// Checks every state of `plan` (see the file comment). `terrain` is the world-frame terrain
/// mesh, `surfaces` its contact surfaces (AffordanceExtractor). Throws InputError for an invalid
/// config, an empty plan or a state with non-finite numbers; every other problem is a violation.
PlanCheckReport CheckPlan(const RobotModel& robot, const TriangleMesh& terrain,
                          const std::vector<AffordanceSurface>& surfaces, const ContactPlan& plan,
                          const PlanCheckConfig& config);

/// CheckPlan with everything taken from a configuration folder, as check_plan does: the robot
/// (robots/anymal_b.*), the surfaces extracted from the scenario's terrain with affordance.yaml,
/// and PlanCheckConfig::FromConfigs with equilibrium.yaml and stance.yaml. Throws InputError for bad files.
PlanCheckReport CheckPlanForScenario(const std::string& config_dir, const Scenario& scenario,
                                     const ContactPlan& plan);

/// The report as JSON: {ok, states, violation_count, violations: [{state, check, detail}],
/// min_robustness_N, max_torque_Nm, min_support_margin_m, walk}; walk is null for an untimed
/// plan, else {ok, violations, min_zmp_margin_m, max_torque_Nm}; infinite values are written as
/// null.
nlohmann::json PlanCheckReportToJson(const PlanCheckReport& report);

}  // namespace rbcp
