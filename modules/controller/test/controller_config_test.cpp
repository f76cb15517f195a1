#include "rbcp/controller/controller_config.h"

#include <gtest/gtest.h>

#include "rbcp/test_support/error_of.h"

namespace rbcp {
namespace {

using test_support::ErrorOf;

const std::string kConfigFile = std::string(RBCP_SOURCE_DIR) + "/config/controller.yaml";

TEST(ControllerConfig, TheShippedFileLoads) {
  const ControllerConfig c = ControllerConfig::LoadFile(kConfigFile);
  EXPECT_EQ(c.torque_limit_Nm, 40.0);
  EXPECT_EQ(c.base.speed_mps, 0.15);
  EXPECT_EQ(c.swing.kp, Eigen::Vector3d(90, 180, 150));
}

TEST(ControllerConfig, RejectsUnknownMissingAndOutOfRangeKeys) {
  YAML::Node node = YAML::LoadFile(kConfigFile);
  YAML::Node extra = YAML::Clone(node);
  extra["swing"]["apex"] = 0.1;
  EXPECT_NE(ErrorOf([&] { ControllerConfig::Load(YamlMap(extra, "c")); }).find("apex"), std::string::npos);
  YAML::Node missing = YAML::Clone(node);
  missing["stance"].remove("load_s");
  EXPECT_NE(ErrorOf([&] { ControllerConfig::Load(YamlMap(missing, "c")); }).find("load_s"), std::string::npos);
  YAML::Node bad = YAML::Clone(node);
  bad["swing"]["touchdown_phase"] = 1.5;
  EXPECT_NE(ErrorOf([&] { ControllerConfig::Load(YamlMap(bad, "c")); }).find("touchdown_phase"), std::string::npos);
}

}  // namespace
}  // namespace rbcp
