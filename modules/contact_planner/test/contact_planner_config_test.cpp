#include "rbcp/contact_planner/contact_planner_config.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

const std::string kFile = std::string(RBCP_SOURCE_DIR) + "/config/contact_planner.yaml";

ContactPlannerConfig LoadNode(const YAML::Node& node) { return ContactPlannerConfig::Load(YamlMap(node, "test")); }

/// Loading `node` throws an InputError whose message names `key`.
void ExpectRejectedNaming(const YAML::Node& node, const std::string& key) {
  try {
    LoadNode(node);
    FAIL() << "expected InputError naming " << key;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(ContactPlannerConfigTest, TheShippedFileHoldsTheDefaults) {
  const ContactPlannerConfig c = ContactPlannerConfig::LoadFile(kFile);
  EXPECT_EQ(DifferingFields(c, ContactPlannerConfig()), std::vector<std::string>{});
  EXPECT_EQ(c.path_step_s, 0.02);
  EXPECT_EQ(c.foothold.lead_time_s, 0.6);
  EXPECT_EQ(c.base_pose.pitch_follow, 0.6);
  EXPECT_GT(c.retry.max_evaluations, 0);
  EXPECT_EQ(c.foothold.lead_time_factors[0], 1.0);
  EXPECT_GT(c.workspace.max_hip_distance_m, 0.0);
  EXPECT_GT(c.time_budget_s, 0.0);
  EXPECT_GE(c.path_yaw_smoothing_s, 0.0);
  for (double lateral : c.base_shift.lateral_offsets_m) EXPECT_LE(std::abs(lateral), c.base_shift.max_base_shift_m);
}

TEST(ContactPlannerConfigTest, RejectsUnknownMissingAndOutOfRangeKeys) {
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["surprise"] = 1;
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["foothold"]["extra"] = 2;
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n.remove("time_budget_s");
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["workspace"]["max_forward_m"] = -0.1;
    ExpectRejectedNaming(n, "max_forward_m");
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["foothold"]["lead_time_factors"] = std::vector<double>{1.0, 0.5};
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["step_time_resolution_s"] = 0.5;  // coarser than the path step
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["path_yaw_smoothing_s"] = -0.1;
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["gait_advance_s"] = -0.25;
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["base_pose"]["pitch_follow"] = 1.5;
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["retry"]["max_evaluations"] = 0;
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["base_shift"]["keep_fraction"] = 1.2;
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["retry"]["keep_fraction"] = std::vector<double>{1.0, -0.5};
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["base_shift"]["lateral_offsets_m"] = std::vector<double>{0.5, -0.1};  // beyond max_base_shift_m
    ExpectRejectedNaming(n, "test: base_shift: 'lateral_offsets_m[0]': expected a number in "
                            "[-max_base_shift_m, max_base_shift_m] [m] (-max_base_shift_m = -0.16, "
                            "max_base_shift_m = 0.16), got 0.5");
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["base_shift"].remove("height_offsets_m");
    EXPECT_THROW(LoadNode(n), InputError);
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["merge"]["workspace_scale"] = 0.8;  // a merge would keep a foot only where the search does not
    ExpectRejectedNaming(n, "test: merge: 'workspace_scale'");
  }
  {
    YAML::Node n = YAML::LoadFile(kFile);
    n["merge"].remove("enabled");
    EXPECT_THROW(LoadNode(n), InputError);
  }
}

}  // namespace
}  // namespace rbcp
