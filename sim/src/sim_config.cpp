#include "rbcp/sim/sim_config.h"

#include <cmath>

namespace rbcp::sim {

int SimConfig::StepsPerTick() const {
  return static_cast<int>(std::lround(1.0 / (control_rate_hz * physics.time_step_s)));
}

}  // namespace rbcp::sim
