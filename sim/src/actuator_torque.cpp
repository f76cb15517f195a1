// The actuators of the simulated robot.

#include <algorithm>
#include <cmath>

#include "rbcp/sim/bullet_world.h"

namespace rbcp::sim {

double ActuatorTorque(double tau_command, double qd, double torque_limit_Nm, double velocity_limit_radps) {
  const double tau = std::clamp(tau_command, -torque_limit_Nm, torque_limit_Nm);
  if (std::abs(qd) >= velocity_limit_radps && tau * qd > 0.0) return 0.0;
  return tau;
}

}  // namespace rbcp::sim
