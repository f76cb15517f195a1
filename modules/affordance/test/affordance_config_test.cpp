#include "rbcp/affordance/affordance_config.h"

#include <gtest/gtest.h>

#include "rbcp/affordance/affordance_extractor.h"

namespace rbcp {
namespace {

std::string LoadError(const std::string& yaml) {
  try {
    AffordanceConfig::Load(YamlMap(YAML::Load(yaml), "aff.yaml"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kValid = "{max_inclination_deg: 30, neighbour_angle_deg: 5, min_area: 1e-3, edge_margin: 0.05}";

TEST(AffordanceConfig, TheShippedFileHoldsTheDefaults) {
  const AffordanceConfig c = AffordanceConfig::LoadFile(std::string(RBCP_SOURCE_DIR) + "/config/affordance.yaml");
  EXPECT_EQ(DifferingFields(c, AffordanceConfig()), std::vector<std::string>{});
  EXPECT_NO_THROW(AffordanceConfig().Validate());
}

TEST(AffordanceConfig, ReadsEveryKey) {
  const AffordanceConfig c = AffordanceConfig::Load(YamlMap(YAML::Load(kValid), "aff.yaml"));
  EXPECT_DOUBLE_EQ(c.max_inclination_deg, 30.0);
  EXPECT_DOUBLE_EQ(c.neighbour_angle_deg, 5.0);
  EXPECT_DOUBLE_EQ(c.min_area, 1e-3);
  EXPECT_DOUBLE_EQ(c.edge_margin, 0.05);
}

TEST(AffordanceConfig, StrictAboutKeysAndRanges) {
  EXPECT_EQ(LoadError("{max_inclination_deg: 30, neighbour_angle_deg: 5, min_area: 1e-3}"),
            "aff.yaml: 'edge_margin': missing key");
  EXPECT_EQ(LoadError("{max_inclination_deg: 30, neighbour_angle_deg: 5, min_area: 1e-3, edge_margin: 0.05, foo: 1}"),
            "aff.yaml: 'foo': unknown key");
  EXPECT_EQ(LoadError("{max_inclination_deg: 95, neighbour_angle_deg: 5, min_area: 1e-3, edge_margin: 0.05}"),
            "aff.yaml: 'max_inclination_deg': expected a number in (0, 90) [deg], got 95");
  EXPECT_EQ(LoadError("{max_inclination_deg: 30, neighbour_angle_deg: 0, min_area: 1e-3, edge_margin: 0.05}"),
            "aff.yaml: 'neighbour_angle_deg': expected a number in (0, 90) [deg], got 0");
  EXPECT_EQ(LoadError("{max_inclination_deg: 30, neighbour_angle_deg: 5, min_area: -1, edge_margin: 0.05}"),
            "aff.yaml: 'min_area': expected a non-negative number [m^2], got -1");
  EXPECT_EQ(LoadError("{max_inclination_deg: 30, neighbour_angle_deg: 5, min_area: 0, edge_margin: -0.01}"),
            "aff.yaml: 'edge_margin': expected a non-negative number [m], got -0.01");
  EXPECT_EQ(LoadError("{max_inclination_deg: 30, neighbour_angle_deg: 5, min_area: 0, edge_margin: x}"),
            "aff.yaml: 'edge_margin': expected a number, got 'x'");
}

TEST(AffordanceConfig, ExtractorRejectsAnOutOfRangeConfig) {
  AffordanceConfig c;
  c.edge_margin = -0.5;
  try {
    AffordanceExtractor extractor(c);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "affordance config: 'edge_margin': expected a non-negative number [m], got -0.5");
  }
}

}  // namespace
}  // namespace rbcp
