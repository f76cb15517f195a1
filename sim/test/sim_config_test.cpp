#include "rbcp/sim/sim_config.h"

#include <gtest/gtest.h>

#include "rbcp/test_support/error_of.h"

namespace rbcp::sim {
namespace {

using rbcp::test_support::ErrorOf;

const std::string kFile = std::string(RBCP_SOURCE_DIR) + "/config/sim.yaml";

std::string ErrorWith(const std::string& key, const std::string& value) {
  YAML::Node node = YAML::LoadFile(kFile);
  node[key] = YAML::Load(value);
  return ErrorOf([&] { SimConfig::Load(YamlMap(node, "sim.yaml")); });
}

TEST(SimConfig, TheShippedFileHoldsTheDefaults) {
  const SimConfig c = SimConfig::LoadFile(kFile);
  EXPECT_EQ(DifferingFields(c, SimConfig()), std::vector<std::string>{});
  EXPECT_EQ(c.StepsPerTick(), 3);
}

TEST(SimConfig, TheControlRateDividesThePhysicsRate) {
  EXPECT_EQ(ErrorWith("control_rate_hz", "600"), "");
  EXPECT_EQ(ErrorWith("control_rate_hz", "500"),
            "sim.yaml: 'control_rate_hz': expected a rate that divides the physics rate (a whole number of physics "
            "steps per tick), got 500 (2.4 steps of 1200 Hz)");
  EXPECT_EQ(ErrorWith("control_rate_hz", "2400"),
            "sim.yaml: 'control_rate_hz': expected a number in [1, 1 / physics.time_step_s] [Hz] "
            "(1 / physics.time_step_s = 1200), got 2400");
}

TEST(SimConfig, RejectsOutOfRangeAndUnknownKeysInItsMaps) {
  YAML::Node node = YAML::LoadFile(kFile);
  node["outcome"]["max_slip_m"] = 0.0;
  EXPECT_EQ(ErrorOf([&] { SimConfig::Load(YamlMap(node, "sim.yaml")); }),
            "sim.yaml: outcome: 'max_slip_m': expected a positive number [m], got 0");
  node = YAML::LoadFile(kFile);
  node["physics"]["joint_velocity_limit_radps"] = 15.0;  // the robot model's
  EXPECT_EQ(ErrorOf([&] { SimConfig::Load(YamlMap(node, "sim.yaml")); }),
            "sim.yaml: physics: 'joint_velocity_limit_radps': unknown key");
}

/// The error of the shipped file with sensing's `sensor` map (or sensing itself for "") given
/// `key: value`.
std::string SensingErrorWith(const std::string& sensor, const std::string& key, const std::string& value) {
  YAML::Node node = YAML::LoadFile(kFile);
  YAML::Node map = sensor.empty() ? node["sensing"] : node["sensing"][sensor];
  map[key] = YAML::Load(value);
  return ErrorOf([&] { SimConfig::Load(YamlMap(node, "sim.yaml")); });
}

TEST(SimConfig, RejectsBadSensorsNamingTheKey) {
  EXPECT_EQ(SensingErrorWith("front_camera", "columns", "16"), "");
  EXPECT_EQ(SensingErrorWith("front_camera", "columns", "0"),
            "sim.yaml: sensing: front_camera: 'columns': expected an integer in [1, 4096], got 0");
  EXPECT_EQ(SensingErrorWith("rear_camera", "min_range_m", "3.5"),
            "sim.yaml: sensing: rear_camera: 'max_range_m': expected a range above min_range_m, got 3.5");
  EXPECT_EQ(SensingErrorWith("front_camera", "horizontal_fov_deg", "180"),
            "sim.yaml: sensing: front_camera: 'horizontal_fov_deg': expected a number in (0, 170] [deg], got 180");
  EXPECT_EQ(SensingErrorWith("", "rate_hz", "40"), "");
  EXPECT_EQ(SensingErrorWith("", "rate_hz", "30"),
            "sim.yaml: sensing: 'rate_hz': expected a rate that divides control_rate_hz (a whole number of control "
            "ticks per capture), got 30 (13.3333 ticks of 400 Hz)");
  EXPECT_EQ(SensingErrorWith("", "rate_hz", "800"),
            "sim.yaml: sensing: 'rate_hz': expected a rate that divides control_rate_hz (a whole number of control "
            "ticks per capture), got 800 (0.5 ticks of 400 Hz)");
  EXPECT_EQ(SensingErrorWith("", "range_noise_m", "-0.01"),
            "sim.yaml: sensing: 'range_noise_m': expected a number in [0, 1] [m], got -0.01");
  EXPECT_EQ(SensingErrorWith("", "noise_seed", "-1").find("sim.yaml: sensing: 'noise_seed'"), 0u);
}

}  // namespace
}  // namespace rbcp::sim
