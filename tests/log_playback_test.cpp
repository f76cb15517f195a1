// Log playback: the committed log holds a TERRAIN message and the AFFORDANCES answer recorded
// from a run of the pipeline; replaying the terrain into the affordance node must reproduce the
// recorded surfaces.
#include <gtest/gtest.h>

#include "rbcp/core/yaml_reader.h"
#include "rbcp/nodes/affordance_node.h"
#include "rbcp/transport/convert.h"
#include "support/affordance_log.h"

namespace rbcp {
namespace {

TEST(LogPlayback, ReplayedTerrainGivesTheRecordedSurfaces) {
  const std::string kLog = testing::AffordanceLogPath();
  const auto events = testing::ReadLog(kLog);
  ASSERT_FALSE(events.empty()) << "cannot read " << kLog;
  const testing::RecordedPair recorded = testing::FindPair(events);
  ASSERT_FALSE(recorded.terrain.data.empty()) << "no TERRAIN event in " << kLog;
  ASSERT_GT(recorded.affordances.num_surfaces, 0) << "no AFFORDANCES answer in " << kLog;

  lcm::LCM lcm("memq://");
  const auto config = AffordanceConfig::Load(YamlMap::LoadFile(std::string(RBCP_SOURCE_DIR) + "/config/affordance.yaml"));
  nodes::AffordanceNode node(lcm, config);
  node.status().set_verbose(false);
  transport::LatestMessage<rbcp_msgs::affordance_set_t> out(lcm, channels::kAffordances);

  lcm.publish(recorded.terrain.channel, recorded.terrain.data.data(), static_cast<unsigned>(recorded.terrain.data.size()));
  while (lcm.handleTimeout(0) > 0) {
  }
  ASSERT_TRUE(node.Step());
  while (lcm.handleTimeout(0) > 0) {
  }
  auto got = out.Take();
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->utime, recorded.affordances.utime);
  testing::ExpectSameSurfaces(*got, recorded.affordances);
}

}  // namespace
}  // namespace rbcp
