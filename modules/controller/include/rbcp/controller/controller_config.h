#pragma once
/// Parameters of the onboard plan controller (config/controller.yaml): gains and timings. What a
/// stance and a swing must satisfy is the stance rules' (config/stance.yaml), shared with the
/// planner; the torque limit is the robot's (RobotModel::ContinuousTorqueLimit). Every key is
/// required and no other key is accepted.

#include <Eigen/Core>
#include <string>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/yaml_reader.h"

namespace rbcp {

/// How the trunk moves between steps and how it is held (virtual model on the base pose).
struct BaseMotionConfig {
  double speed_mps = 0.15;
  double yaw_rate_radps = 0.25;
  double min_shift_s = 0.3;
  double settle_s = 0.5;
  double final_hold_s = 0.5;
  Eigen::Vector3d kp_linear = Eigen::Vector3d(435, 400, 350);
  Eigen::Vector3d kd_linear = Eigen::Vector3d(80, 90, 95);
  Eigen::Vector3d kp_angular = Eigen::Vector3d(40, 90, 40);
  Eigen::Vector3d kd_angular = Eigen::Vector3d(8, 20, 17);

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("speed_mps", &speed_mps, "m/s", bounds::Positive(), "speed of a base shift");
    v->Visit("yaw_rate_radps", &yaw_rate_radps, "rad/s", bounds::Positive(), "turn rate of a base shift");
    v->Visit("min_shift_s", &min_shift_s, "s", bounds::Positive(), "shortest base shift");
    v->Visit("settle_s", &settle_s, "s", bounds::NonNegative(), "hold of the start stance before the first step");
    v->Visit("final_hold_s", &final_hold_s, "s", bounds::NonNegative(), "hold of the final stance after the last step");
    v->Visit("kp_linear", &kp_linear, "N/m", bounds::NonNegative(), "virtual model on the base position, base axes");
    v->Visit("kd_linear", &kd_linear, "N s/m", bounds::NonNegative(), "its damping, base axes");
    v->Visit("kp_angular", &kp_angular, "N m/rad", bounds::NonNegative(), "virtual model on the base orientation, base axes");
    v->Visit("kd_angular", &kd_angular, "N m s/rad", bounds::NonNegative(), "its damping, base axes");
  }
};

/// The swing of a foot from its old foothold to its new one (its path: StanceConfig::swing).
struct SwingConfig {
  double touchdown_phase = 0.6;
  double search_depth_m = 0.08;
  double search_speed_mps = 0.15;
  double tip_margin_m = 0.01;
  double tip_hold_s = 0.02;
  double tip_speedup = 2.5;
  Eigen::Vector3d kp = Eigen::Vector3d(90, 180, 150);
  Eigen::Vector3d kd = Eigen::Vector3d(3, 5.7, 4.9);

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("touchdown_phase", &touchdown_phase, "", bounds::Closed(0, 1),
             "a contact before this phase of the swing is a late lift-off or a bump, after it a touchdown");
    v->Visit("search_depth_m", &search_depth_m, "m", bounds::NonNegative(),
             "a foot that ends its path without contact reaches down at most this far ...");
    v->Visit("search_speed_mps", &search_speed_mps, "m/s", bounds::Positive(),
             "... at this speed; then it has found no ground");
    v->Visit("tip_margin_m", &tip_margin_m, "m", bounds::NonNegative(),
             "when the centre of pressure of the stance feet comes this close to the edge of their polygon during "
             "a swing (the robot tips towards the leg in the air, say after a push) ...");
    v->Visit("tip_hold_s", &tip_hold_s, "s", bounds::Closed(0.0, 1.0),
             "... and stays there this long (a stance foot's contact lost for a tick is no tip) ...");
    v->Visit("tip_speedup", &tip_speedup, "", bounds::AtLeast(1.0),
             "... the rest of the swing runs this many times faster, to put the foot down sooner");
    v->Visit("kp", &kp, "N m/rad", bounds::NonNegative(), "joint PD of a swing leg, (HAA, HFE, KFE)");
    v->Visit("kd", &kd, "N m s/rad", bounds::NonNegative(), "its damping");
  }
};

/// Stance legs: joint PD (their contact forces: StanceRules; their load ramps: the stance
/// library's walk, StanceConfig::dynamic_walk).
struct StanceLegConfig {
  Eigen::Vector3d kp = Eigen::Vector3d(30, 30, 15);
  Eigen::Vector3d kd = Eigen::Vector3d(3, 5.7, 4.9);

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("kp", &kp, "N m/rad", bounds::NonNegative(), "joint PD of a stance leg, (HAA, HFE, KFE)");
    v->Visit("kd", &kd, "N m s/rad", bounds::NonNegative(), "its damping");
  }
};

/// How the controller walks a plan.
enum class WalkMode {
  /// A static crawl: the base shifts with four feet down, then stands still while a leg swings.
  kStatic,
  /// A walking pattern (walking_pattern.h): the CoM follows ZMP preview control over the coming
  /// support polygons and moves while a leg swings; four feet are down only between two swings.
  kDynamic,
};

/// The names of the walk modes in configuration files and on command lines.
inline const EnumNames<WalkMode>& WalkModeNames() {
  static const EnumNames<WalkMode> names = {{WalkMode::kStatic, "static"}, {WalkMode::kDynamic, "dynamic"}};
  return names;
}

struct ControllerConfig {
  WalkMode mode = WalkMode::kStatic;
  BaseMotionConfig base;
  SwingConfig swing;
  StanceLegConfig stance;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("mode", &mode, WalkModeNames(),
             "static: a crawl with the base still during a swing; dynamic: the CoM moves on a ZMP preview");
    v->Visit("base", &base, "how the trunk moves between steps and how it is held");
    v->Visit("swing", &swing, "the swing of a foot");
    v->Visit("stance", &stance, "the legs on the ground");
  }

  static ControllerConfig Load(const YamlMap& map) { return LoadConfig<ControllerConfig>(map); }
  static ControllerConfig LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
  /// Throws InputError naming the first out-of-range value.
  void Validate(const std::string& where = "ControllerConfig") const { ValidateConfig(*this, where); }
};

}  // namespace rbcp
