#include "rbcp/stance/stance_config.h"

#include <cmath>

#include "rbcp/core/config_checks.h"
#include "rbcp/equilibrium/config.h"

namespace rbcp {

StanceConfig StanceConfig::Load(const YamlMap& map) {
  StanceConfig c;
  c.support_margin_m = map.Double("support_margin_m");
  c.torque_limit_fraction = map.Double("torque_limit_fraction");
  c.min_normal_force_N = map.Double("min_normal_force_N");
  c.thigh_clearance_m = map.Double("thigh_clearance_m");
  c.trunk_clearance_m = map.Double("trunk_clearance_m");
  c.transit_checks = map.Int("transit_checks");
  const YamlMap swing = map.Map("swing");
  c.swing.height_m = swing.Double("height_m");
  c.swing.terrain_clearance_m = swing.Double("terrain_clearance_m");
  c.swing.speed_mps = swing.Double("speed_mps");
  c.swing.min_duration_s = swing.Double("min_duration_s");
  c.swing.touchdown_depth_m = swing.Double("touchdown_depth_m");
  c.swing.body_clearance = swing.Bool("body_clearance");
  swing.RejectUnknownKeys();
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

StanceConfig StanceConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

StanceRules StanceRules::LoadFromDir(const std::string& config_dir) {
  StanceRules rules;
  rules.config = StanceConfig::LoadFile(config_dir + "/stance.yaml");
  rules.friction = EquilibriumConfig::LoadFile(config_dir + "/equilibrium.yaml").friction;
  return rules;
}

void StanceConfig::Validate(const std::string& where) const {
  const ConfigChecks check(where);
  check.NonNegative("support_margin_m", support_margin_m, "m");
  if (!(std::isfinite(torque_limit_fraction) && torque_limit_fraction > 0.0 && torque_limit_fraction <= 1.0)) {
    check.Fail("torque_limit_fraction", "a number in (0, 1]", ConfigNumber(torque_limit_fraction));
  }
  check.NonNegative("min_normal_force_N", min_normal_force_N, "N");
  if (!(std::isfinite(thigh_clearance_m) && thigh_clearance_m >= 0.0 && thigh_clearance_m < 0.1)) {
    check.Fail("thigh_clearance_m", "a clearance in [0, 0.1) m", ConfigNumber(thigh_clearance_m));
  }
  if (!(std::isfinite(trunk_clearance_m) && trunk_clearance_m >= 0.0 && trunk_clearance_m < 0.1)) {
    check.Fail("trunk_clearance_m", "a clearance in [0, 0.1) m", ConfigNumber(trunk_clearance_m));
  }
  check.AtLeast("transit_checks", transit_checks, 1);
  check.NonNegative("swing.height_m", swing.height_m, "m");
  check.NonNegative("swing.terrain_clearance_m", swing.terrain_clearance_m, "m");
  check.Positive("swing.speed_mps", swing.speed_mps, "m/s");
  check.Positive("swing.min_duration_s", swing.min_duration_s, "s");
  check.NonNegative("swing.touchdown_depth_m", swing.touchdown_depth_m, "m");
}

}  // namespace rbcp
