#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "rbcp/mapping/terrain_map.h"
#include "rbcp/test_support/error_of.h"

namespace rbcp::mapping {
namespace {

using test_support::ErrorOf;

const std::string kConfigFile = std::string(RBCP_SOURCE_DIR) + "/config/mapper.yaml";

TEST(MapperConfig, TheShippedFileHoldsTheDefaults) {
  const MapperConfig c = MapperConfig::LoadFile(kConfigFile);
  EXPECT_EQ(DifferingFields(c, MapperConfig()), std::vector<std::string>{});
  EXPECT_EQ(c.elevation.resolution_m, 0.04);
  EXPECT_EQ(c.elevation.window_m, 8.0);
  EXPECT_EQ(c.occupancy.resolution_m, 0.05);
  EXPECT_EQ(c.publish_period_s, 0.5);
  EXPECT_NO_THROW(c.Validate());
}

TEST(MapperConfig, RejectsUnknownMissingAndOutOfRangeKeys) {
  const YAML::Node node = YAML::LoadFile(kConfigFile);
  YAML::Node extra = YAML::Clone(node);
  extra["occupancy"]["hit_probability"] = 0.7;
  EXPECT_NE(ErrorOf([&] { MapperConfig::Load(YamlMap(extra, "m")); }).find("hit_probability"), std::string::npos);
  YAML::Node missing = YAML::Clone(node);
  missing["elevation"].remove("gate_sigma");
  EXPECT_NE(ErrorOf([&] { MapperConfig::Load(YamlMap(missing, "m")); }).find("gate_sigma"), std::string::npos);
  YAML::Node bad = YAML::Clone(node);
  bad["occupancy"]["clear_probability"] = 0.7;
  EXPECT_NE(ErrorOf([&] { MapperConfig::Load(YamlMap(bad, "m")); }).find("clear_probability"), std::string::npos);
  YAML::Node nan = YAML::Clone(node);
  nan["elevation"]["resolution_m"] = ".nan";
  EXPECT_NE(ErrorOf([&] { MapperConfig::Load(YamlMap(nan, "m")); }).find("resolution_m"), std::string::npos);
  YAML::Node huge = YAML::Clone(node);
  huge["elevation"]["window_m"] = 1000.0;  // 25000 cells a side
  EXPECT_NE(ErrorOf([&] { MapperConfig::Load(YamlMap(huge, "m")); }).find("window_m"), std::string::npos);
  YAML::Node zero = YAML::Clone(node);
  zero["max_points_per_cloud"] = 0;
  EXPECT_NE(ErrorOf([&] { MapperConfig::Load(YamlMap(zero, "m")); }).find("max_points_per_cloud"), std::string::npos);
}

TEST(MapperConfig, TheMapsRejectAnInvalidConfig) {
  MapperConfig c;
  c.elevation.recenter_distance_m = 5.0;  // beyond half the 8 m window
  EXPECT_NE(ErrorOf([&] { TerrainMap map(c); }).find("recenter_distance_m"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { ElevationMap map(c.elevation); }).find("recenter_distance_m"), std::string::npos);
}

}  // namespace
}  // namespace rbcp::mapping
