#pragma once
/// Parameters of the onboard plan controller (config/controller.yaml): gains and timings. What a
/// stance and a swing must satisfy is the stance rules' (config/stance.yaml), shared with the
/// planner. Every key is required and no other key is accepted.

#include <Eigen/Core>
#include <string>

#include "rbcp/core/yaml_reader.h"

namespace rbcp {

/// How the trunk moves between steps and how it is held (virtual model on the base pose).
struct BaseMotionConfig {
  double speed_mps = 0.15;          ///< base speed of a shift [m/s]
  double yaw_rate_radps = 0.25;     ///< base turn rate of a shift [rad/s]
  double min_shift_s = 0.3;         ///< shortest shift [s]
  double settle_s = 0.5;            ///< hold of the start stance before the first step [s]
  double final_hold_s = 0.5;        ///< hold of the final stance after the last step [s]
  Eigen::Vector3d kp_linear = Eigen::Vector3d(435, 400, 350);   ///< [N/m], base axes
  Eigen::Vector3d kd_linear = Eigen::Vector3d(80, 90, 95);      ///< [N s/m], base axes
  Eigen::Vector3d kp_angular = Eigen::Vector3d(40, 90, 40);     ///< [N m/rad], base axes
  Eigen::Vector3d kd_angular = Eigen::Vector3d(8, 20, 17);      ///< [N m s/rad], base axes
};

/// The swing of a foot from its old foothold to its new one (its path: StanceConfig::swing).
struct SwingConfig {
  /// A contact in the swing's first part is a late lift-off or a bump; from this phase [0, 1] on
  /// it is an (early) touchdown.
  double touchdown_phase = 0.6;
  double search_depth_m = 0.08;        ///< a late touchdown reaches down at most this far [m] ...
  double search_speed_mps = 0.15;      ///< ... at this speed [m/s]; then the foot has found no ground
  Eigen::Vector3d kp = Eigen::Vector3d(90, 180, 150);  ///< joint PD of a swing leg, (HAA, HFE, KFE) [N m/rad]
  Eigen::Vector3d kd = Eigen::Vector3d(3, 5.7, 4.9);   ///< [N m s/rad]
};

/// Stance legs: load ramps and joint PD (their contact forces: StanceRules).
struct StanceLegConfig {
  double unload_s = 0.15;              ///< load ramp of a leg before lift-off [s]
  double load_s = 0.1;                 ///< load ramp of a leg after touchdown [s]
  Eigen::Vector3d kp = Eigen::Vector3d(30, 30, 15);    ///< joint PD of a stance leg [N m/rad]
  Eigen::Vector3d kd = Eigen::Vector3d(3, 5.7, 4.9);   ///< [N m s/rad]
};

struct ControllerConfig {
  double torque_limit_Nm = 40.0;  ///< command limit of the actuators [N m]
  BaseMotionConfig base;
  SwingConfig swing;
  StanceLegConfig stance;

  static ControllerConfig Load(const YamlMap& map);
  static ControllerConfig LoadFile(const std::string& path);
  /// Throws InputError naming the first out-of-range value.
  void Validate(const std::string& where = "ControllerConfig") const;
};

}  // namespace rbcp
