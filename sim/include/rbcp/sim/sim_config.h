#pragma once
/// The simulator's configuration (config/sim.yaml): the physics, the process's rates, how a run
/// is judged, and the depth sensors. Every key is required and no other key is accepted. The robot's limits (torque,
/// joint speed) are the robot model's.

#include <cmath>
#include <string>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/sim/bullet_world.h"
#include "rbcp/sim/depth_sensor.h"

namespace rbcp::sim {

/// How the simulator judges the execution of a plan. These are outcome checks, not controller
/// parameters: the controller never sees them.
struct OutcomeConfig {
  double max_tilt_rad = 0.5;
  double max_slip_m = 0.03;
  double max_saturation_s = 0.2;
  double goal_tolerance_m = 0.1;
  double contact_release_s = 0.02;
  double timeout_base_s = 20.0;
  double timeout_per_step_s = 4.0;
  double trace_rate_hz = 20.0;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("max_tilt_rad", &max_tilt_rad, "rad", bounds::Positive(), "fall: roll or pitch this far from the plan's");
    v->Visit("max_slip_m", &max_slip_m, "m", bounds::Positive(),
             "foot slip: the contact point of a foot slid this far along the terrain since touchdown (rolling excluded)");
    v->Visit("max_saturation_s", &max_saturation_s, "s", bounds::Positive(),
             "a joint's torque held at the limit longer than this fails the run");
    v->Visit("goal_tolerance_m", &goal_tolerance_m, "m", bounds::Positive(),
             "goal: the base this close to the plan's final base, four feet down");
    v->Visit("contact_release_s", &contact_release_s, "s", bounds::NonNegative(),
             "a foot out of contact this long has lifted off (slip tracking restarts)");
    v->Visit("timeout_base_s", &timeout_base_s, "s", bounds::Positive(),
             "a run may last timeout_base_s + timeout_per_step_s x steps");
    v->Visit("timeout_per_step_s", &timeout_per_step_s, "s", bounds::NonNegative(), "see timeout_base_s");
    v->Visit("trace_rate_hz", &trace_rate_hz, "Hz", bounds::Positive(), "samples of the run's trace");
  }
};

struct SimConfig {
  PhysicsConfig physics;
  double control_rate_hz = 400.0;
  double terrain_period_s = 1.0;
  double drop_height_m = 0.002;
  OutcomeConfig outcome;
  SensingConfig sensing;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("physics", &physics, "the physical world: ANYmal B as a Bullet btMultiBody built from the URDF");
    const double physics_rate_hz = 1.0 / physics.time_step_s;
    const double steps_per_tick = physics_rate_hz / control_rate_hz;
    v->Visit("control_rate_hz", &control_rate_hz, "Hz",
             bounds::AtLeast(1.0).AtMost(physics_rate_hz, "1 / physics.time_step_s"),
             "the onboard controller runs, and ROBOT_STATE is published, at this rate of simulated time");
    v->Rule("control_rate_hz", std::abs(steps_per_tick - std::round(steps_per_tick)) <= 1e-6,
            "a rate that divides the physics rate (a whole number of physics steps per tick)",
            ConfigNumber(control_rate_hz) + " (" + ConfigNumber(steps_per_tick) + " steps of " +
                ConfigNumber(physics_rate_hz) + " Hz)");
    v->Visit("terrain_period_s", &terrain_period_s, "s", bounds::Positive(),
             "TERRAIN is republished this often (simulated time) for late processes");
    v->Visit("drop_height_m", &drop_height_m, "m", bounds::Closed(0, 0.1),
             "the robot is placed this far above the terrain, at rest, to start");
    v->Visit("outcome", &outcome, "how the simulator judges a run (the controller never sees these)");
    v->Map("sensing", "simulated depth sensors on the trunk, published on POINT_CLOUD (sim/include/rbcp/sim/depth_sensor.h)",
           [&](auto* m) {
             sensing.Serialize(m);
             const double ticks = control_rate_hz / sensing.rate_hz;
             m->Rule("rate_hz", ticks >= 1.0 - 1e-9 && std::abs(ticks - std::round(ticks)) <= 1e-6,
                     "a rate that divides control_rate_hz (a whole number of control ticks per capture)",
                     ConfigNumber(sensing.rate_hz) + " (" + ConfigNumber(ticks) + " ticks of " +
                         ConfigNumber(control_rate_hz) + " Hz)");
           });
  }

  /// Physics steps per control tick (control_rate_hz must divide the physics rate).
  int StepsPerTick() const;

  static SimConfig Load(const YamlMap& map) { return LoadConfig<SimConfig>(map); }
  static SimConfig LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
  void Validate(const std::string& where = "SimConfig") const { ValidateConfig(*this, where); }
};

}  // namespace rbcp::sim
