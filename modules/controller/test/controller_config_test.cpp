#include "rbcp/controller/controller_config.h"

#include <gtest/gtest.h>

#include "rbcp/test_support/error_of.h"

namespace rbcp {
namespace {

using test_support::ErrorOf;

const std::string kConfigFile = std::string(RBCP_SOURCE_DIR) + "/config/controller.yaml";

TEST(ControllerConfig, TheShippedFileHoldsTheDefaults) {
  const ControllerConfig c = ControllerConfig::LoadFile(kConfigFile);
  EXPECT_EQ(DifferingFields(c, ControllerConfig()), std::vector<std::string>{});
  EXPECT_EQ(c.base.speed_mps, 0.15);
  EXPECT_EQ(c.swing.kp, Eigen::Vector3d(90, 180, 150));
}

TEST(ControllerConfig, RejectsUnknownMissingAndOutOfRangeKeys) {
  YAML::Node node = YAML::LoadFile(kConfigFile);
  YAML::Node extra = YAML::Clone(node);
  extra["swing"]["apex"] = 0.1;
  EXPECT_NE(ErrorOf([&] { ControllerConfig::Load(YamlMap(extra, "c")); }).find("apex"), std::string::npos);
  YAML::Node missing = YAML::Clone(node);
  missing["stance"].remove("kd");
  EXPECT_NE(ErrorOf([&] { ControllerConfig::Load(YamlMap(missing, "c")); }).find("kd"), std::string::npos);
  YAML::Node bad = YAML::Clone(node);
  bad["swing"]["touchdown_phase"] = 1.5;
  EXPECT_EQ(ErrorOf([&] { ControllerConfig::Load(YamlMap(bad, "c")); }),
            "c: swing: 'touchdown_phase': expected a number in [0, 1], got 1.5");
  YAML::Node limit = YAML::Clone(node);
  limit["torque_limit_Nm"] = 40.0;  // the robot's (RobotModel::ContinuousTorqueLimit)
  EXPECT_EQ(ErrorOf([&] { ControllerConfig::Load(YamlMap(limit, "c")); }), "c: 'torque_limit_Nm': unknown key");
}

}  // namespace
}  // namespace rbcp
