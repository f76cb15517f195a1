#include "rbcp/sim/sim_config.h"

#include <cmath>

#include "rbcp/core/config_checks.h"

namespace rbcp::sim {

OutcomeConfig OutcomeConfig::Load(const YamlMap& map) {
  OutcomeConfig c;
  c.max_tilt_rad = map.Double("max_tilt_rad");
  c.max_slip_m = map.Double("max_slip_m");
  c.max_saturation_s = map.Double("max_saturation_s");
  c.goal_tolerance_m = map.Double("goal_tolerance_m");
  c.contact_release_s = map.Double("contact_release_s");
  c.timeout_base_s = map.Double("timeout_base_s");
  c.timeout_per_step_s = map.Double("timeout_per_step_s");
  c.trace_rate_hz = map.Double("trace_rate_hz");
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

void OutcomeConfig::Validate(const std::string& where) const {
  const ConfigChecks check(where);
  check.Positive("max_tilt_rad", max_tilt_rad, "rad");
  check.Positive("max_slip_m", max_slip_m, "m");
  check.Positive("max_saturation_s", max_saturation_s, "s");
  check.Positive("goal_tolerance_m", goal_tolerance_m, "m");
  check.NonNegative("contact_release_s", contact_release_s, "s");
  check.Positive("timeout_base_s", timeout_base_s, "s");
  check.NonNegative("timeout_per_step_s", timeout_per_step_s, "s");
  check.Positive("trace_rate_hz", trace_rate_hz, "Hz");
}

int SimConfig::StepsPerTick() const {
  return static_cast<int>(std::lround(1.0 / (control_rate_hz * physics.time_step_s)));
}

SimConfig SimConfig::Load(const YamlMap& map) {
  SimConfig c;
  c.physics = PhysicsConfig::Load(map.Map("physics"));
  c.outcome = OutcomeConfig::Load(map.Map("outcome"));
  c.control_rate_hz = map.Double("control_rate_hz");
  c.terrain_period_s = map.Double("terrain_period_s");
  c.drop_height_m = map.Double("drop_height_m");
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

SimConfig SimConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

void SimConfig::Validate(const std::string& where) const {
  physics.Validate(where + ": physics");
  outcome.Validate(where + ": outcome");
  const ConfigChecks check(where);
  check.InRange("control_rate_hz", control_rate_hz, 1.0, 1.0 / physics.time_step_s, "Hz");
  const double steps = 1.0 / (control_rate_hz * physics.time_step_s);
  if (std::abs(steps - std::round(steps)) > 1e-6) {
    check.Fail("control_rate_hz", "a rate that divides the physics rate " + ConfigNumber(1.0 / physics.time_step_s) + " Hz",
               ConfigNumber(control_rate_hz));
  }
  check.Positive("terrain_period_s", terrain_period_s, "s");
  check.InRange("drop_height_m", drop_height_m, 0.0, 0.1, "m");
}

}  // namespace rbcp::sim
