#include "rbcp/equilibrium/config.h"

#include <cmath>
#include <sstream>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

EquilibriumConfig EquilibriumConfig::Load(const YamlMap& map) {
  EquilibriumConfig c;
  c.friction = map.Double("friction");
  c.generators_per_contact = map.Int("generators_per_contact");
  c.robustness_threshold_N = map.Double("robustness_threshold_N");
  c.support_margin_m = map.Double("support_margin_m");
  c.normal_force_slack = map.Double("normal_force_slack");
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

EquilibriumConfig EquilibriumConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

void EquilibriumConfig::Validate(const std::string& where) const {
  auto fail = [&](const std::string& key, const std::string& expected, const std::string& got) {
    throw InputError(where + ": '" + key + "': expected " + expected + ", got " + got);
  };
  if (!(std::isfinite(friction) && friction > 0.0)) fail("friction", "a positive number", Num(friction));
  if (generators_per_contact < 3 || generators_per_contact > 64) {
    fail("generators_per_contact", "an integer in [3, 64]", std::to_string(generators_per_contact));
  }
  if (!(std::isfinite(robustness_threshold_N) && robustness_threshold_N >= 0.0)) {
    fail("robustness_threshold_N", "a non-negative number [N]", Num(robustness_threshold_N));
  }
  if (!(std::isfinite(support_margin_m) && support_margin_m >= 0.0)) {
    fail("support_margin_m", "a non-negative number [m]", Num(support_margin_m));
  }
  if (!(std::isfinite(normal_force_slack) && normal_force_slack >= 0.0 && normal_force_slack <= 1.0)) {
    fail("normal_force_slack", "a number in [0, 1]", Num(normal_force_slack));
  }
}

}  // namespace rbcp
