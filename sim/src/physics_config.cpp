// PhysicsConfig: the `physics:` map of config/sim.yaml, read strictly.

#include <algorithm>
#include <cmath>

#include "rbcp/core/config_checks.h"
#include "rbcp/sim/bullet_world.h"

namespace rbcp::sim {

PhysicsConfig PhysicsConfig::Load(const YamlMap& map) {
  PhysicsConfig c;
  c.gravity_mps2 = map.Double("gravity_mps2");
  c.time_step_s = map.Double("time_step_s");
  c.solver_iterations = map.Int("solver_iterations");
  c.friction = map.Double("friction");
  c.torque_limit_Nm = map.Double("torque_limit_Nm");
  c.joint_velocity_limit_radps = map.Double("joint_velocity_limit_radps");
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

void PhysicsConfig::Validate(const std::string& where) const {
  const ConfigChecks check(where);
  check.NonNegative("gravity_mps2", gravity_mps2, "m/s^2");
  if (!(std::isfinite(time_step_s) && time_step_s > 0.0 && time_step_s <= kMaxTimeStep_s)) {
    check.Fail("time_step_s", "a number in (0, " + ConfigNumber(kMaxTimeStep_s) + "] [s]", ConfigNumber(time_step_s));
  }
  check.AtLeast("solver_iterations", solver_iterations, 1);
  check.Positive("friction", friction);
  check.Positive("torque_limit_Nm", torque_limit_Nm, "N m");
  check.Positive("joint_velocity_limit_radps", joint_velocity_limit_radps, "rad/s");
}

double ActuatorTorque(double tau_command, double qd, double torque_limit_Nm, double velocity_limit_radps) {
  const double tau = std::clamp(tau_command, -torque_limit_Nm, torque_limit_Nm);
  if (std::abs(qd) >= velocity_limit_radps && tau * qd > 0.0) return 0.0;
  return tau;
}

}  // namespace rbcp::sim
