#include "rbcp/equilibrium/config.h"

#include "rbcp/core/config_checks.h"

namespace rbcp {

EquilibriumConfig EquilibriumConfig::Load(const YamlMap& map) {
  EquilibriumConfig c;
  c.friction = map.Double("friction");
  c.generators_per_contact = map.Int("generators_per_contact");
  c.robustness_threshold_N = map.Double("robustness_threshold_N");
  c.normal_force_slack = map.Double("normal_force_slack");
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

EquilibriumConfig EquilibriumConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

void EquilibriumConfig::Validate(const std::string& where) const {
  const ConfigChecks check(where);
  check.Positive("friction", friction);
  check.InRange("generators_per_contact", generators_per_contact, 3, 64);
  check.NonNegative("robustness_threshold_N", robustness_threshold_N, "N");
  check.InRange("normal_force_slack", normal_force_slack, 0.0, 1.0);
}

}  // namespace rbcp
