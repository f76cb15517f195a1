#include "rbcp/nodes/offline_pipeline.h"

#include <gtest/gtest.h>

#include "rbcp/core/error.h"

namespace rbcp::nodes {
namespace {

const std::string kConfig = std::string(RBCP_SOURCE_DIR) + "/config";

TEST(OfflinePipeline, RootStageOnFlatGroundGivesAStablePathAndJson) {
  const OfflinePipeline pipeline(kConfig);
  const Scenario scenario = LoadScenario(kConfig + "/scenarios/flat_ground.yaml");
  const PipelineResult a = pipeline.Run(scenario, PipelineStage::kRoot, 4, 5.0);
  ASSERT_TRUE(a.ok()) << a.failure;
  ASSERT_TRUE(a.root.has_value());
  const auto json = ToJson(a);
  for (const char* key : {"affordance_ms", "root_ok", "root_s", "root_path", "failure"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_TRUE(json["root_ok"].get<bool>());
  EXPECT_TRUE(json["failure"].is_null());
  const auto& first = json["root_path"].front();
  EXPECT_EQ(first["position"].size(), 3u);
  EXPECT_EQ(first["velocity"].size(), 3u);
  EXPECT_TRUE(first.contains("t") && first.contains("yaw"));

  const PipelineResult b = pipeline.Run(scenario, PipelineStage::kRoot, 4, 5.0);
  ASSERT_EQ(a.root->samples.size(), b.root->samples.size());
  for (std::size_t i = 0; i < a.root->samples.size(); ++i) {
    EXPECT_EQ(a.root->samples[i].p, b.root->samples[i].p) << "same seed, same path";
  }
}

TEST(OfflinePipeline, AffordanceStageOnlyAndBadStageName) {
  const OfflinePipeline pipeline(kConfig);
  const PipelineResult r =
      pipeline.Run(LoadScenario(kConfig + "/scenarios/plinth.yaml"), PipelineStage::kAffordance, 1, 1.0);
  EXPECT_TRUE(r.ok());
  EXPECT_FALSE(r.root.has_value());
  EXPECT_FALSE(ToJson(r).contains("root_ok"));
  EXPECT_THROW(ParseStage("contacts"), InputError);
}

}  // namespace
}  // namespace rbcp::nodes
