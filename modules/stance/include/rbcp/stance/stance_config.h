#pragma once
/// What a stance and a step must satisfy (config/stance.yaml): read by the contact planner, which
/// chooses stances that satisfy it, by the controller, which walks them as planned, and by the
/// plan checker. Every key is required and no other key is accepted.

#include <string>

#include "rbcp/core/yaml_reader.h"

namespace rbcp {

/// The path of a swinging foot (SwingTrajectory).
struct SwingPathConfig {
  double height_m = 0.08;             ///< apex above the higher of the two footholds [m]
  double terrain_clearance_m = 0.05;  ///< least height of the foot above the terrain under its path [m]
  double speed_mps = 0.8;             ///< peak foot speed along the path [m/s]
  double min_duration_s = 0.45;       ///< shortest swing [s]
  double touchdown_depth_m = 0.01;    ///< the path ends this far below the foothold [m]
  /// The swinging leg also keeps clear of the trunk and the other legs along the whole path; false
  /// only prefers it (the path touches them at as few samples as it can).
  bool body_clearance = true;
};

struct StanceConfig {
  /// The CoM's ground projection lies this far inside the support polygon of the feet that carry
  /// the robot: the four feet while the base moves, the three that stay during a swing [m].
  double support_margin_m = 0.04;
  /// Static joint torques, with the weight spread over the stance feet as the controller spreads
  /// it, stay below this share of the actuators' command limit [-], in (0, 1].
  double torque_limit_fraction = 0.85;
  /// Least normal force of a loaded stance foot in that spread (the controller's force
  /// distribution) [N].
  double min_normal_force_N = 15.0;
  /// The thighs (with the knee actuators) keep this clear of the terrain, in every stance and
  /// along every swing [m], in [0, 0.1).
  double thigh_clearance_m = 0.015;
  /// The trunk (body, belly plate, hip actuators) keeps this clear of the terrain [m], in [0, 0.1).
  double trunk_clearance_m = 0.01;
  /// Intermediate base poses checked while the base moves between two states [-], >= 1.
  int transit_checks = 6;
  SwingPathConfig swing;

  static StanceConfig Load(const YamlMap& map);
  static StanceConfig LoadFile(const std::string& path);
  /// Throws InputError naming the first out-of-range value.
  void Validate(const std::string& where = "StanceConfig") const;
};

/// Everything the stance checks are configured by: stance.yaml, and the friction coefficient the
/// force distribution assumes, which is the static-equilibrium tests' (equilibrium.yaml).
struct StanceRules {
  StanceConfig config;
  double friction = 0.5;  ///< [-]

  /// Reads config_dir/stance.yaml and the friction of config_dir/equilibrium.yaml. Throws InputError.
  static StanceRules LoadFromDir(const std::string& config_dir);
};

}  // namespace rbcp
