#include "rbcp/controller/controller_config.h"

#include "rbcp/core/config_checks.h"

namespace rbcp {
namespace {

void PositiveVector(const ConfigChecks& check, const std::string& key, const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) check.NonNegative(key + "[" + std::to_string(i) + "]", v[i]);
}

}  // namespace

ControllerConfig ControllerConfig::Load(const YamlMap& map) {
  ControllerConfig c;
  c.torque_limit_Nm = map.Double("torque_limit_Nm");
  const YamlMap base = map.Map("base");
  c.base.speed_mps = base.Double("speed_mps");
  c.base.yaw_rate_radps = base.Double("yaw_rate_radps");
  c.base.min_shift_s = base.Double("min_shift_s");
  c.base.settle_s = base.Double("settle_s");
  c.base.final_hold_s = base.Double("final_hold_s");
  c.base.kp_linear = base.Vector3("kp_linear");
  c.base.kd_linear = base.Vector3("kd_linear");
  c.base.kp_angular = base.Vector3("kp_angular");
  c.base.kd_angular = base.Vector3("kd_angular");
  base.RejectUnknownKeys();
  const YamlMap swing = map.Map("swing");
  c.swing.touchdown_phase = swing.Double("touchdown_phase");
  c.swing.search_depth_m = swing.Double("search_depth_m");
  c.swing.search_speed_mps = swing.Double("search_speed_mps");
  c.swing.kp = swing.Vector3("kp");
  c.swing.kd = swing.Vector3("kd");
  swing.RejectUnknownKeys();
  const YamlMap stance = map.Map("stance");
  c.stance.unload_s = stance.Double("unload_s");
  c.stance.load_s = stance.Double("load_s");
  c.stance.kp = stance.Vector3("kp");
  c.stance.kd = stance.Vector3("kd");
  stance.RejectUnknownKeys();
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

ControllerConfig ControllerConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

void ControllerConfig::Validate(const std::string& where) const {
  const ConfigChecks check(where);
  check.Positive("torque_limit_Nm", torque_limit_Nm, "N m");
  check.Positive("base.speed_mps", base.speed_mps, "m/s");
  check.Positive("base.yaw_rate_radps", base.yaw_rate_radps, "rad/s");
  check.Positive("base.min_shift_s", base.min_shift_s, "s");
  check.NonNegative("base.settle_s", base.settle_s, "s");
  check.NonNegative("base.final_hold_s", base.final_hold_s, "s");
  PositiveVector(check, "base.kp_linear", base.kp_linear);
  PositiveVector(check, "base.kd_linear", base.kd_linear);
  PositiveVector(check, "base.kp_angular", base.kp_angular);
  PositiveVector(check, "base.kd_angular", base.kd_angular);
  check.InRange("swing.touchdown_phase", swing.touchdown_phase, 0.0, 1.0);
  check.NonNegative("swing.search_depth_m", swing.search_depth_m, "m");
  check.Positive("swing.search_speed_mps", swing.search_speed_mps, "m/s");
  PositiveVector(check, "swing.kp", swing.kp);
  PositiveVector(check, "swing.kd", swing.kd);
  check.Positive("stance.unload_s", stance.unload_s, "s");
  check.Positive("stance.load_s", stance.load_s, "s");
  PositiveVector(check, "stance.kp", stance.kp);
  PositiveVector(check, "stance.kd", stance.kd);
}

}  // namespace rbcp
