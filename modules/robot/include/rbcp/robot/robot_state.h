#pragma once
/// The measured state of the robot, as the simulator (or the robot's drivers and state
/// estimator) reports it at its state rate and ROBOT_STATE carries it. The onboard controller
/// sees only this (and the terrain).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "rbcp/core/leg.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {

struct RobotState {
  double t = 0.0;  ///< simulated time [s]

  Eigen::Vector3d base_position_W = Eigen::Vector3d::Zero();                 ///< [m], world frame
  Eigen::Quaterniond base_orientation_W = Eigen::Quaterniond::Identity();    ///< base to world
  Eigen::Vector3d base_linear_velocity_W = Eigen::Vector3d::Zero();          ///< [m/s], world frame
  Eigen::Vector3d base_angular_velocity_B = Eigen::Vector3d::Zero();         ///< [rad/s], base frame

  JointVector q = JointVector::Zero();    ///< joint positions [rad], LF, RF, LH, RH x (HAA, HFE, KFE)
  JointVector qd = JointVector::Zero();   ///< joint velocities [rad/s]
  JointVector tau = JointVector::Zero();  ///< joint torques applied in the last step [N m]

  std::array<bool, kNumLegs> foot_contact{};  ///< foot touches the terrain, LF, RF, LH, RH
  /// Contact force the terrain exerts on each foot [N], world frame (zero without contact).
  std::array<Eigen::Vector3d, kNumLegs> foot_force_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                                     Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
};

/// What the onboard controller is doing, published beside the measured state on its own channel
/// (CONTROLLER_STATUS): a state estimator's ROBOT_STATE does not carry it.
struct ControllerProgress {
  int64_t plan_seq = 0;  ///< sequence number of the plan being walked (0: none yet)
  int steps_done = 0;    ///< steps executed since the start, over all plans
  /// Set while the controller stands at a step boundary waiting for a plan that starts from this
  /// stance: the time [us] the wait began (it identifies the boundary).
  std::optional<int64_t> awaiting_since;
  std::string phase = "hold";  ///< the controller's phase (ToString(ControllerPhase))
  int step = 0;                ///< plan state being walked to
  int swing_leg = -1;          ///< Index(Leg) of the leg unloading, swinging or reloading; -1 none
  double base_error_m = 0.0;   ///< measured base to the reference it tracks [m]
  double step_max_base_error_m = 0.0;  ///< the largest base_error_m of the current step [m]
  double support_margin_m = 0.0;       ///< CoM inside the polygon of the loaded feet [m]
  /// Steps after the current one whose motion the controller already prepares for (the dynamic
  /// walk's preview, PlanController::CommittedSteps): a replacing plan keeps them.
  int steps_committed = 0;
  double lag_s = 0.0;  ///< dynamic walk: time the gait's clock stood still for late steps [s]
};

}  // namespace rbcp
