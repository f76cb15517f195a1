#include "rbcp/nodes/affordance_node.h"

#include <gtest/gtest.h>

#include <limits>

#include "rbcp/transport/convert.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"

namespace rbcp::nodes {
namespace {

class AffordanceNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm_.good());
    node_.status().set_verbose(false);
  }
  void Pump() {
    while (lcm_.handleTimeout(0) > 0) {
    }
  }
  static TriangleMesh Floor(double z) {
    TriangleMesh box = MakeBoxMesh({2.0, 1.0, 0.2});
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0, 0, z - 0.1);
    box.Transform(T);
    return box;
  }

  lcm::LCM lcm_{"memq://"};
  AffordanceNode node_{lcm_, AffordanceConfig{}};
  transport::LatestMessage<rbcp_msgs::affordance_set_t> affordances_{lcm_, channels::kAffordances};
  transport::LatestMessage<rbcp_msgs::process_status_t> status_{lcm_, channels::kStatus};
};

TEST_F(AffordanceNodeTest, NothingToDoWithoutTerrain) {
  Pump();
  EXPECT_FALSE(node_.Step());
  node_.Heartbeat();
  Pump();
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::ALIVE);
  EXPECT_EQ(status_.Latest()->process, "affordance_extractor");
}

TEST_F(AffordanceNodeTest, TerrainBecomesSurfacesAndOkStatus) {
  const auto terrain = transport::ToTerrainMsg(Floor(0.25), 1000, "floor");
  lcm_.publish(channels::kTerrain, &terrain);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  auto out = affordances_.Take();
  ASSERT_TRUE(out.has_value());
  EXPECT_EQ(out->utime, 1000);
  ASSERT_EQ(out->num_surfaces, 1);
  EXPECT_NEAR(out->surfaces[0].normal[2], 1.0, 1e-12);
  EXPECT_NEAR(out->surfaces[0].vertices[0][2], 0.25, 1e-9);
  const double m = AffordanceConfig{}.edge_margin;
  EXPECT_NEAR(out->surfaces[0].area, (2.0 - 2 * m) * (1.0 - 2 * m), 1e-9);
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
  EXPECT_EQ(status_.Latest()->input_utime, 1000);
  EXPECT_FALSE(node_.Step()) << "the same terrain must not be handled twice";
}

TEST_F(AffordanceNodeTest, NewestTerrainSupersedesOlderOnes) {
  const auto first = transport::ToTerrainMsg(Floor(0.0), 1, "a");
  const auto second = transport::ToTerrainMsg(Floor(0.5), 2, "b");
  lcm_.publish(channels::kTerrain, &first);
  lcm_.publish(channels::kTerrain, &second);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_EQ(affordances_.received(), 1);
  EXPECT_EQ(affordances_.Latest()->utime, 2);
  EXPECT_NEAR(affordances_.Latest()->surfaces[0].vertices[0][2], 0.5, 1e-9);
}

TEST_F(AffordanceNodeTest, NanTerrainFailsWithReasonAndPublishesNoSurfaces) {
  auto terrain = transport::ToTerrainMsg(Floor(0.0), 5, "bad");
  terrain.vertices[3][2] = std::numeric_limits<double>::quiet_NaN();
  lcm_.publish(channels::kTerrain, &terrain);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_FALSE(affordances_.Take().has_value());
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(status_.Latest()->reason, "terrain mesh: vertex 3 is not finite");
  EXPECT_EQ(status_.Latest()->input_utime, 5);
}

TEST_F(AffordanceNodeTest, GarbageOnTheTerrainChannelFailsWithReason) {
  const char garbage[] = "\x01\x02\x03";
  lcm_.publish(channels::kTerrain, garbage, sizeof(garbage));
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  ASSERT_TRUE(status_.Latest().has_value());
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(status_.Latest()->reason.find("cannot decode TERRAIN"), std::string::npos);
  // A good terrain afterwards is handled normally.
  const auto terrain = transport::ToTerrainMsg(Floor(0.0), 9, "ok");
  lcm_.publish(channels::kTerrain, &terrain);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
}

TEST_F(AffordanceNodeTest, ATerrainSentInPartsIsExtractedWhole) {
  // A 2 m x 1 m floor of 300 x 150 cells (90,000 triangles): about 2.2 MB, above the 1 MB that
  // goes whole.
  TriangleMesh grid;
  const int nx = 300, ny = 150;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) grid.vertices.emplace_back(-1.0 + 2.0 * i / nx, -0.5 + 1.0 * j / ny, 0.1);
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, d = a + nx + 1, c = d + 1;
      grid.triangles.push_back({a, b, c});
      grid.triangles.push_back({a, c, d});
    }
  }
  const auto terrain = transport::ToTerrainMsg(grid, 77, "grid");
  ASSERT_GT(terrain.getEncodedSize(), 2000000);
  transport::PartOptions options;
  options.pause_s = 0.0;
  transport::MessagePublisher publisher(lcm_, options);
  ASSERT_EQ(publisher.Publish(channels::kTerrain, terrain), "");
  EXPECT_EQ(publisher.parted_messages(), 1);
  EXPECT_GE(publisher.parts_sent(), 8);
  Pump();
  ASSERT_TRUE(node_.Step());
  Pump();
  const auto out = affordances_.Take();
  ASSERT_TRUE(out.has_value()) << (status_.Latest() ? status_.Latest()->reason : "no status");
  EXPECT_EQ(out->utime, 77);
  ASSERT_EQ(out->num_surfaces, 1);
  const double m = AffordanceConfig{}.edge_margin;
  EXPECT_NEAR(out->surfaces[0].area, (2.0 - 2 * m) * (1.0 - 2 * m), 1e-9);
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK);
}

}  // namespace
}  // namespace rbcp::nodes
