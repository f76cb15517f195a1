#include "rbcp/stance/stance_config.h"

#include <gtest/gtest.h>

#include "rbcp/test_support/error_of.h"

namespace rbcp {
namespace {

using test_support::ErrorOf;

const std::string kConfigFile = std::string(RBCP_SOURCE_DIR) + "/config/stance.yaml";

TEST(StanceConfig, TheShippedFileHoldsTheDefaults) {
  const StanceConfig c = StanceConfig::LoadFile(kConfigFile);
  EXPECT_EQ(DifferingFields(c, StanceConfig()), std::vector<std::string>{});
  EXPECT_EQ(c.support_margin_m, 0.04);
  EXPECT_EQ(c.torque_limit_fraction, 0.85);
  EXPECT_EQ(c.swing.height_m, 0.08);
  EXPECT_TRUE(c.swing.body_clearance);
}

TEST(StanceConfig, RejectsUnknownMissingAndOutOfRangeKeys) {
  const YAML::Node node = YAML::LoadFile(kConfigFile);
  YAML::Node extra = YAML::Clone(node);
  extra["swing"]["apex"] = 0.1;
  EXPECT_NE(ErrorOf([&] { StanceConfig::Load(YamlMap(extra, "s")); }).find("apex"), std::string::npos);
  YAML::Node missing = YAML::Clone(node);
  missing.remove("support_margin_m");
  EXPECT_NE(ErrorOf([&] { StanceConfig::Load(YamlMap(missing, "s")); }).find("support_margin_m"), std::string::npos);
  YAML::Node bad = YAML::Clone(node);
  bad["torque_limit_fraction"] = 1.5;
  EXPECT_NE(ErrorOf([&] { StanceConfig::Load(YamlMap(bad, "s")); }).find("torque_limit_fraction"), std::string::npos);
  YAML::Node nan = YAML::Clone(node);
  nan["swing"]["speed_mps"] = ".nan";
  EXPECT_NE(ErrorOf([&] { StanceConfig::Load(YamlMap(nan, "s")); }).find("speed_mps"), std::string::npos);
}

}  // namespace
}  // namespace rbcp
