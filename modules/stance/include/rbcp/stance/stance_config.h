#pragma once
/// What a stance and a step must satisfy (config/stance.yaml): read by the contact planner, which
/// chooses stances that satisfy it, by the controller, which walks them as planned, and by the
/// plan checker. Every key is required and no other key is accepted.

#include <string>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/equilibrium/config.h"
#include "rbcp/stance/gait_config.h"

namespace rbcp {

/// The path of a swinging foot (SwingTrajectory).
struct SwingPathConfig {
  double height_m = 0.08;
  double terrain_clearance_m = 0.05;
  double speed_mps = 0.8;
  double min_duration_s = 0.45;
  double touchdown_depth_m = 0.01;
  bool body_clearance = true;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("height_m", &height_m, "m", bounds::NonNegative(), "apex above the higher of the two footholds");
    v->Visit("terrain_clearance_m", &terrain_clearance_m, "m", bounds::NonNegative(),
             "least height of the foot above the terrain under the middle of its path");
    v->Visit("speed_mps", &speed_mps, "m/s", bounds::Positive(),
             "peak foot speed up, across and down (the swing lasts as long as that needs)");
    v->Visit("min_duration_s", &min_duration_s, "s", bounds::Positive(), "shortest swing");
    v->Visit("touchdown_depth_m", &touchdown_depth_m, "m", bounds::NonNegative(),
             "the path ends this far below the foothold, so that the foot touches down");
    v->Visit("body_clearance", &body_clearance,
             "the leg keeps clear of the trunk and the other legs along the whole path (false: the path touches "
             "them at as few samples as it can)");
  }
};

struct StanceConfig {
  double support_margin_m = 0.04;
  double torque_limit_fraction = 0.85;
  double min_normal_force_N = 15.0;
  double thigh_clearance_m = 0.015;
  double trunk_clearance_m = 0.01;
  int transit_checks = 6;
  SwingPathConfig swing;
  DynamicWalkConfig dynamic_walk;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("support_margin_m", &support_margin_m, "m", bounds::NonNegative(),
             "the CoM's ground projection lies this far inside the support polygon of the feet that carry the robot: "
             "the four feet while the base moves, the three that stay during a swing");
    v->Visit("torque_limit_fraction", &torque_limit_fraction, "", bounds::Positive().AtMost(1.0),
             "static joint torques, the weight spread over the stance feet as the controller spreads it, stay below "
             "this share of the robot's continuous torque limit (the rest is the controller's: joint servo, base "
             "motion, load ramps)");
    v->Visit("min_normal_force_N", &min_normal_force_N, "N", bounds::NonNegative(),
             "least normal force of a loaded stance foot in the controller's force distribution");
    v->Visit("thigh_clearance_m", &thigh_clearance_m, "m", bounds::NonNegative().Below(0.1),
             "the thighs and knee actuators keep this clear of the terrain, standing and swinging (the walked base "
             "is off its plan by a centimetre)");
    v->Visit("trunk_clearance_m", &trunk_clearance_m, "m", bounds::NonNegative().Below(0.1),
             "the body, belly plate and hip actuators keep this clear of the terrain");
    v->Visit("transit_checks", &transit_checks, "", bounds::AtLeast(1),
             "intermediate base poses checked while the base moves from one state's pose to the next");
    v->Visit("swing", &swing, "the path of a swinging foot");
    v->Visit("dynamic_walk", &dynamic_walk,
             "the clock of the dynamic walk, which times every step of a plan (the controller's mode dynamic)");
  }

  static StanceConfig Load(const YamlMap& map) { return LoadConfig<StanceConfig>(map); }
  static StanceConfig LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
  /// Throws InputError naming the first out-of-range value.
  void Validate(const std::string& where = "StanceConfig") const { ValidateConfig(*this, where); }
};

/// Everything the stance checks are configured by: stance.yaml, and the friction coefficient the
/// force distribution assumes, which is the static-equilibrium tests' (equilibrium.yaml).
struct StanceRules {
  StanceConfig config;
  double friction = EquilibriumConfig().friction;  ///< [-]

  /// Reads config_dir/stance.yaml and the friction of config_dir/equilibrium.yaml. Throws InputError.
  static StanceRules LoadFromDir(const std::string& config_dir);
};

}  // namespace rbcp
