#pragma once
/// The physical world the robot lives in: ANYmal B as a Bullet btMultiBody built from its URDF,
/// on the scenario's terrain, integrated with a fixed step. This is the only place that knows the
/// true world; everything else sees RobotState.
///
/// Physics (PhysicsConfig, config/sim.yaml `physics:`): gravity, URDF masses and inertias, a
/// fixed step (stepSimulation(dt, 0)), the foot-terrain friction as the combined coefficient,
/// implicit cone friction off, the commanded torque saturated at the robot's continuous torque
/// limit and cut when a joint is at the robot's joint speed limit (both RobotModel's, from the
/// planning parameters beside the URDF), joint position limits from the URDF. Bullet types do not
/// leave this header's implementation.
///
/// The robot as built: a floating base (the URDF "base" link) and one Bullet link per revolute
/// joint, in the whole-robot joint order; each shank carries its adapter tube (fixed joint
/// merged: masses added, inertias combined about the common centre of mass), and each
/// <LEG>_FOOT is a fixed link of its own with the foot sphere as its only collider, so foot
/// contacts are told apart by their collider. Bullet places every link at its centre of mass in
/// its principal axes; that is internal: every pose here is a URDF link frame (the base pose is
/// the "base" link origin, not the centre of mass). Joint signs are the URDF's: a positive joint
/// position turns the child link about the URDF axis by the right-hand rule, as RobotModel has it.
///
/// Contacts: combined friction = robot collider (config friction) x terrain (1). Friction is a
/// pyramid of two directions per contact point (the first along the sliding velocity), each
/// bounded by friction x normal impulse. Self-collision between non-adjacent links is on, except
/// for primitive pairs that already overlap in the reference configuration (the thighs' upper
/// protector and heat-fin box around the HAA actuators), the same rule as the planners' check.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/leg.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/robot/robot_state.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp::sim {

/// Physical parameters of the simulation (the `physics` map of config/sim.yaml).
struct PhysicsConfig {
  double gravity_mps2 = 9.81;
  /// 1/1200 s, to the digits sim.yaml gives.
  double time_step_s = 0.000833333333333;
  int solver_iterations = 30;
  double friction = 0.8;

  static constexpr double kMaxTimeStep_s = 1e-3;  ///< largest accepted time_step_s [s]

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("gravity_mps2", &gravity_mps2, "m/s^2", bounds::NonNegative(), "gravity along world -z");
    v->Visit("time_step_s", &time_step_s, "s", bounds::Positive().AtMost(kMaxTimeStep_s),
             "fixed integration step (stiff joint PD and contacts need a small one)");
    v->Visit("solver_iterations", &solver_iterations, "", bounds::AtLeast(1),
             "contact and limit solver iterations per step");
    v->Visit("friction", &friction, "", bounds::Positive(),
             "Coulomb friction of every robot-terrain contact (the combined coefficient: terrain colliders use 1)");
  }

  /// Reads the map: every key above is required, unknown keys are rejected, then Validate.
  /// Throws InputError.
  static PhysicsConfig Load(const YamlMap& map) { return LoadConfig<PhysicsConfig>(map); }
  /// Throws InputError naming the first out-of-range value.
  void Validate(const std::string& where = "PhysicsConfig") const { ValidateConfig(*this, where); }
};

/// The torque a joint actuator delivers for a command [N m]: the command saturated at
/// +-torque_limit_Nm, and zero when the joint turns at or beyond velocity_limit_radps (|qd|) and
/// the torque has the sign of qd, i.e. would speed it up further. Torques that brake the joint
/// are always delivered. BulletWorld applies this to every joint in every step.
double ActuatorTorque(double tau_command, double qd, double torque_limit_Nm, double velocity_limit_radps);

/// One contact between a robot link and the terrain, as Bullet's contact manifolds hold it.
struct TerrainContact {
  std::string link;                                      ///< URDF link name, e.g. "LF_FOOT", "base", "RH_THIGH"
  std::optional<Leg> leg;                                ///< nullopt for the trunk
  bool is_foot = false;                                  ///< the contact is on a foot sphere
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();  ///< contact point on the robot's surface [m]
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();   ///< from the terrain towards the robot
  double normal_force_N = 0.0;                           ///< normal impulse of the last step / time step [N]
  /// Overlap of the shapes when the step began [m]: > 0 inside, < 0 for a point still apart
  /// that the solver pushed on (speculative contact).
  double penetration_m = 0.0;
};

class BulletWorld {
 public:
  /// Builds the world: the robot from the model's links and joints (every link with mass and
  /// inertia, every collision primitive, fixed joints merged into their parent, the feet as fixed
  /// links), the terrain elements (boxes as exact box shapes, meshes as static triangle meshes).
  /// The robot starts at rest in the model's reference configuration 1 m above the origin until
  /// ResetRobot is called. The world keeps no reference to `robot`. Throws InputError for a bad
  /// terrain or config.
  BulletWorld(const RobotModel& robot, const std::vector<TerrainElement>& terrain, const PhysicsConfig& config);
  ~BulletWorld();
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  /// Places the robot at rest: base pose (world frame, base to world) and joint positions.
  /// Clears velocities, commanded torques, contacts and the time. Nothing checks that the
  /// robot is clear of the terrain: a pose inside it is pushed out by the contact solver.
  void ResetRobot(const Eigen::Vector3d& base_position_W, const Eigen::Quaterniond& base_orientation_W,
                  const JointVector& q);

  /// Commands joint torques [N m] for the following steps (held until the next call). Each is
  /// saturated at the robot's continuous torque limit; at or beyond its joint speed limit a torque that would speed the
  /// joint up further is cut to zero (ActuatorTorque, re-evaluated in every step with the joint
  /// velocity of that step). Returns the torques the next step will apply. Throws InputError for
  /// a non-finite torque.
  JointVector SetJointTorques(const JointVector& tau_command);

  /// Replaces the terrain (a box added or removed while the robot walks): the old static bodies
  /// leave the world and the new ones enter it; the robot is not moved. Throws InputError for an
  /// invalid element.
  void SetTerrain(const std::vector<TerrainElement>& terrain);

  /// An external force on the base at its centre of mass [N], world frame, applied in every
  /// following step until changed (zero: none). Throws InputError for a non-finite force.
  void SetBaseForce(const Eigen::Vector3d& force_W);

  /// Advances the world by one fixed step of time_step_s (one Bullet step of exactly that length:
  /// collision detection, contact and limit solve, semi-implicit Euler integration).
  void Step();

  /// Simulated time since construction or the last ResetRobot [s].
  double Time() const;

  /// The measured state: base pose (base link origin) and twist (linear velocity of that origin
  /// in the world frame, angular velocity in the base frame), joint positions, velocities and
  /// the torques applied in the last step, and per foot whether it touched the terrain in the
  /// last step and the total force the terrain exerted on it then (normal and friction impulses
  /// of its contact points / time step, world frame). The forces are the solver's: converged,
  /// their sum balances the robot's weight and inertia to a fraction of a newton.
  RobotState State() const;

  /// Centre of each foot sphere [m], world frame (LF, RF, LH, RH).
  std::array<Eigen::Vector3d, kNumLegs> FootCentersW() const;
  /// Each foot sphere's frame in the world: origin at its centre, the foot body's orientation
  /// (LF, RF, LH, RH). The orientation tells how far a sphere rolled.
  std::array<Eigen::Isometry3d, kNumLegs> FootFramesW() const;

  /// Every robot-terrain contact point of the last step with penetration >= 0 or a positive
  /// normal impulse.
  std::vector<TerrainContact> TerrainContacts() const;

  /// Robot-robot (self) contacts of the last step (shapes touching), as distinct pairs of URDF
  /// link names.
  std::vector<std::pair<std::string, std::string>> SelfContacts() const;

  /// Rays against the terrain only (the robot's links are transparent to them): per direction
  /// (world frame, unit) from origin_W, the distance to the first terrain surface within
  /// max_range_m, or +infinity for none; 0 from inside a terrain box. The terrain is the current
  /// one (SetTerrain). A depth sensor's rays (depth_sensor.h).
  void CastTerrainRays(const Eigen::Vector3d& origin_W, const std::vector<Eigen::Vector3d>& directions_W,
                       double max_range_m, std::vector<double>* distances) const;

  /// Total robot mass as built [kg].
  double RobotMass() const;

  const PhysicsConfig& Config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbcp::sim
