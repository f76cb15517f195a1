#include "rbcp/equilibrium/config.h"

#include <gtest/gtest.h>

#include <functional>

#include "rbcp/test_support/error_of.h"

namespace rbcp {
namespace {

using rbcp::test_support::ErrorOf;

constexpr const char* kValid =
    "{friction: 0.7, generators_per_contact: 6, robustness_threshold_N: 3.5, normal_force_slack: 0.02}";

TEST(EquilibriumConfig, TheShippedFileHoldsTheDefaults) {
  const auto c = EquilibriumConfig::LoadFile(std::string(RBCP_SOURCE_DIR) + "/config/equilibrium.yaml");
  EXPECT_EQ(DifferingFields(c, EquilibriumConfig()), std::vector<std::string>{});
  EXPECT_DOUBLE_EQ(c.friction, 0.5);
}

TEST(EquilibriumConfig, ReadsEveryKey) {
  const auto c = EquilibriumConfig::Load(YamlMap(YAML::Load(kValid), "eq"));
  EXPECT_DOUBLE_EQ(c.friction, 0.7);
  EXPECT_EQ(c.generators_per_contact, 6);
  EXPECT_DOUBLE_EQ(c.robustness_threshold_N, 3.5);
  EXPECT_DOUBLE_EQ(c.normal_force_slack, 0.02);
}

TEST(EquilibriumConfig, RejectsMissingUnknownAndOutOfRangeKeys) {
  EXPECT_EQ(ErrorOf([] {
              EquilibriumConfig::Load(YamlMap(
                  YAML::Load("{friction: 0.5, generators_per_contact: 4, robustness_threshold_N: 2}"), "eq"));
            }),
            "eq: 'normal_force_slack': missing key");
  EXPECT_EQ(ErrorOf([] {
              auto node = YAML::Load(kValid);
              node["mu"] = 0.5;
              EquilibriumConfig::Load(YamlMap(node, "eq"));
            }),
            "eq: 'mu': unknown key");
  auto with = [](const char* key, const char* value) {
    auto node = YAML::Load(kValid);
    node[key] = YAML::Load(value);
    return ErrorOf([&] { EquilibriumConfig::Load(YamlMap(node, "eq")); });
  };
  EXPECT_EQ(with("friction", "0"), "eq: 'friction': expected a positive number, got 0");
  EXPECT_EQ(with("friction", "-0.2"), "eq: 'friction': expected a positive number, got -0.2");
  EXPECT_EQ(with("generators_per_contact", "2"), "eq: 'generators_per_contact': expected an integer in [3, 64], got 2");
  EXPECT_EQ(with("generators_per_contact", "4.5"), "eq: 'generators_per_contact': expected an integer, got '4.5'");
  EXPECT_EQ(with("robustness_threshold_N", "-1"),
            "eq: 'robustness_threshold_N': expected a non-negative number [N], got -1");
  EXPECT_EQ(with("normal_force_slack", "1.5"), "eq: 'normal_force_slack': expected a number in [0, 1], got 1.5");
  EXPECT_EQ(with("friction", "[1]"), "eq: 'friction': expected a number, got a list of 1");
}

}  // namespace
}  // namespace rbcp
