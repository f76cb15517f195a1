#pragma once
/// The simulator's configuration (config/sim.yaml): the physics, how a run is judged, and the
/// process's rates. Every key is required and no other key is accepted.

#include <string>

#include "rbcp/core/yaml_reader.h"
#include "rbcp/sim/bullet_world.h"

namespace rbcp::sim {

/// How the simulator judges the execution of a plan. These are outcome checks, not controller
/// parameters: the controller never sees them.
struct OutcomeConfig {
  double max_tilt_rad = 0.5;        ///< fall: roll or pitch this far from the plan's
  double max_slip_m = 0.03;         ///< foot slip: a stance foot this far from where it touched down
  double max_saturation_s = 0.2;    ///< a joint's torque held at its limit this long fails the run
  double goal_tolerance_m = 0.1;    ///< goal: base this close to the plan's final base
  double contact_release_s = 0.02;  ///< a foot without contact this long has lifted off
  double timeout_base_s = 20.0;     ///< a run may last timeout_base_s + timeout_per_step_s x steps
  double timeout_per_step_s = 4.0;
  double trace_rate_hz = 20.0;      ///< rate of the trace samples

  static OutcomeConfig Load(const YamlMap& map);
  void Validate(const std::string& where = "OutcomeConfig") const;
};

struct SimConfig {
  PhysicsConfig physics;
  OutcomeConfig outcome;
  double control_rate_hz = 400.0;   ///< controller and ROBOT_STATE rate (a whole number of physics steps)
  double terrain_period_s = 1.0;    ///< the process republishes TERRAIN this often [s of simulated time]
  double drop_height_m = 0.002;     ///< the robot starts this far above the terrain [m]

  /// Physics steps per control tick (control_rate_hz must divide the physics rate).
  int StepsPerTick() const;

  static SimConfig Load(const YamlMap& map);
  static SimConfig LoadFile(const std::string& path);
  void Validate(const std::string& where = "SimConfig") const;
};

}  // namespace rbcp::sim
