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

}  // namespace
}  // namespace rbcp::sim
