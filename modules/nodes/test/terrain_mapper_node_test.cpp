#include "rbcp/nodes/terrain_mapper_node.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>

#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::nodes {
namespace {

const std::string kConfig = std::string(RBCP_SOURCE_DIR) + "/config";
constexpr double kBaseHeight = 0.45;

/// A sensor on the trunk's front, 0.5 rad down: the one the tests' clouds come from.
Eigen::Isometry3d Mount() {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.translation() = Eigen::Vector3d(0.35, 0.0, 0.05);
  m.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return m;
}

/// The capture of flat ground at z = `ground` by the sensor of Mount() on a base standing at
/// (x, 0, ground + kBaseHeight), level: a grid of rays, each return exact.
rbcp_msgs::point_cloud_t FlatGroundCloud(int64_t utime, double x, double ground = 0.0) {
  rbcp_msgs::point_cloud_t c{};
  c.utime = utime;
  c.sensor = "front_camera";
  c.seq = utime / 100000 + 1;  // a capture every 0.1 s
  const Eigen::Isometry3d mount = Mount();
  const Eigen::Quaterniond q(mount.linear());
  c.base_position[0] = x;
  c.base_position[2] = ground + kBaseHeight;
  c.base_orientation[0] = 1.0;  // level
  for (int k = 0; k < 3; ++k) c.mount_position[k] = mount.translation()[k];
  c.mount_orientation[0] = q.w();
  c.mount_orientation[1] = q.x();
  c.mount_orientation[2] = q.y();
  c.mount_orientation[3] = q.z();
  c.min_range = 0.1f;
  c.max_range = 4.0f;
  c.range_noise_std = 0.0f;
  const Eigen::Vector3d origin_W = Eigen::Vector3d(x, 0.0, ground + kBaseHeight) + mount.translation();
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 48; ++j) {
      const Eigen::Vector3d d_S = Eigen::Vector3d(1.0, -0.6 + 1.2 * i / 63.0, -0.4 + 0.8 * j / 47.0).normalized();
      const Eigen::Vector3d d_W = mount.linear() * d_S;  // the base is level
      c.num_rays += 1;
      if (d_W.z() > -1e-3) continue;
      const double range = (origin_W.z() - ground) / -d_W.z();
      if (range > c.max_range) continue;
      const Eigen::Vector3f p = (range * d_S).cast<float>();
      c.points.push_back({p.x(), p.y(), p.z()});
    }
  }
  c.num_points = static_cast<int32_t>(c.points.size());
  return c;
}

class TerrainMapperNodeTest : public ::testing::Test {
 protected:
  void SetUp() override { node_.status().set_verbose(false); }

  void Pump() {
    while (lcm_.handleTimeout(0) > 0) {
    }
  }
  /// Delivers what was published and steps the node until it has nothing left to do.
  void Run() {
    for (int i = 0; i < 10; ++i) {
      Pump();
      if (!node_.Step()) break;
    }
    Pump();
  }
  /// The standing robot's measured state at `utime`, its base at (x, 0, kBaseHeight), four feet down.
  rbcp_msgs::robot_state_t State(int64_t utime, double x = 0.0) const {
    RobotState s;
    s.t = static_cast<double>(utime) * 1e-6;
    s.base_position_W = Eigen::Vector3d(x, 0.0, kBaseHeight);
    s.q = robot_.ReferenceConfiguration();
    s.foot_contact = {true, true, true, true};
    return transport::ToRobotStateMsg(s);
  }
  std::string LastReason() const { return status_.Latest() ? status_.Latest()->reason : ""; }

  lcm::LCM lcm_{"memq://"};
  RobotModel robot_ = RobotModel::LoadDefault(kConfig);
  mapping::MapperConfig config_ = mapping::MapperConfig::LoadFile(kConfig + "/mapper.yaml");
  TerrainMapperNode node_{lcm_, config_, robot_};
  transport::LatestMessage<rbcp_msgs::terrain_mesh_t> terrain_{lcm_, channels::kTerrain};
  transport::LatestMessage<rbcp_msgs::elevation_map_t> map_{lcm_, channels::kElevationMap};
  transport::LatestMessage<rbcp_msgs::process_status_t> status_{lcm_, channels::kStatus};
};

TEST_F(TerrainMapperNodeTest, ACloudOfFlatGroundBecomesTerrainAtTheGroundsHeight) {
  const auto state = State(0);
  lcm_.publish(channels::kRobotState, &state);
  const auto cloud = FlatGroundCloud(0, 0.0);
  ASSERT_GT(cloud.num_points, 2000);
  lcm_.publish(channels::kPointCloud, &cloud);
  Run();
  const auto terrain = terrain_.Take();
  ASSERT_TRUE(terrain.has_value()) << LastReason();
  EXPECT_EQ(terrain->utime, 0);
  const TriangleMesh mesh = transport::FromTerrainMsg(*terrain);
  ASSERT_GT(mesh.NumTriangles(), 100u);
  double max_x = -1e9;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    EXPECT_NEAR(v.z(), 0.0, 0.01);
    max_x = std::max(max_x, v.x());
  }
  EXPECT_GT(max_x, 1.0) << "the ground ahead is known";
  const auto grid = map_.Take();
  ASSERT_TRUE(grid.has_value());
  EXPECT_EQ(grid->terrain_id, terrain->terrain_id);
  EXPECT_EQ(grid->num_cells, grid->num_x * grid->num_y);
  // The grid comes back from its message cell for cell.
  const mapping::ElevationMap back = FromElevationMapMsg(*grid);
  const mapping::ElevationMap& sent = node_.map().elevation();
  EXPECT_EQ(back.origin(), sent.origin());
  EXPECT_EQ(back.KnownCells(), sent.KnownCells());
  for (int iy = 0; iy < sent.num_y(); iy += 7) {
    for (int ix = 0; ix < sent.num_x(); ix += 7) {
      const auto a = sent.At(ix, iy);
      const auto b = back.At(ix, iy);
      ASSERT_EQ(a.has_value(), b.has_value());
      if (a) {
        EXPECT_NEAR(a->height, b->height, 1e-6);
      }
    }
  }
  EXPECT_EQ(node_.clouds_fused(), 1);
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::OK) << LastReason();
}

TEST_F(TerrainMapperNodeTest, ANewMapStartsWithTheGroundUnderTheStandingRobot) {
  // The cameras never see under the trunk; the robot stands there, on its feet.
  const auto cloud = FlatGroundCloud(0, 0.0);
  lcm_.publish(channels::kPointCloud, &cloud);
  Run();
  ASSERT_EQ(node_.clouds_fused(), 1) << "a cloud needs no ROBOT_STATE: it carries its base pose";
  const mapping::ElevationMap& grid = node_.map().elevation();
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d foot_W = robot_.ReferenceFootPosition(leg) + Eigen::Vector3d(0.0, 0.0, kBaseHeight);
    const auto cell = grid.At(foot_W.head<2>());
    ASSERT_TRUE(cell.has_value()) << "under " << LegName(leg);
    EXPECT_NEAR(cell->height, foot_W.z(), 0.01);
  }
  const auto under_trunk = grid.At(Eigen::Vector2d(0.0, 0.0));
  ASSERT_TRUE(under_trunk.has_value());
  EXPECT_NEAR(under_trunk->height, kBaseHeight + robot_.ReferenceFootPosition(Leg::kLF).z(), 0.01);
}

TEST_F(TerrainMapperNodeTest, ACloudIsPlacedWithTheBasePoseItCarries) {
  // The base pose at capture travels with the cloud: the map does not depend on which states the
  // mapper heard. The same capture carried from 0.5 m further on is mapped 0.5 m further on.
  const auto state = State(0, 0.0);
  const auto near = FlatGroundCloud(0, 0.0);
  auto moved = near;
  moved.base_position[0] = 0.5;
  const auto extent = [&](const rbcp_msgs::point_cloud_t& cloud) {
    TerrainMapperNode node(lcm_, config_, robot_);
    node.status().set_verbose(false);
    lcm_.publish(channels::kPointCloud, &cloud);
    lcm_.publish(channels::kRobotState, &state);  // the state at capture says x = 0 for both
    for (int i = 0; i < 10; ++i) {
      Pump();
      node.Step();
    }
    double max_x = -1e9;
    const mapping::ElevationMap& grid = node.map().elevation();
    for (int iy = 0; iy < grid.num_y(); ++iy) {
      for (int ix = 0; ix < grid.num_x(); ++ix) {
        if (grid.At(ix, iy)) max_x = std::max(max_x, grid.CellCentre(ix, iy).x());
      }
    }
    return max_x;
  };
  const double a = extent(near);
  const double b = extent(moved);
  EXPECT_NEAR(b - a, 0.5, 0.05);
}

TEST_F(TerrainMapperNodeTest, HostileCloudsAreRejectedWithTheReasonAndTheMapperGoesOn) {
  const auto state = State(0);
  lcm_.publish(channels::kRobotState, &state);

  // Points that are not numbers: skipped, the rest is mapped.
  auto nan_points = FlatGroundCloud(0, 0.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < nan_points.points.size(); i += 3) nan_points.points[i] = {nan, 0.0f, 0.0f};
  nan_points.points[1] = {std::numeric_limits<float>::infinity(), 1.0f, 1.0f};
  lcm_.publish(channels::kPointCloud, &nan_points);
  Run();
  EXPECT_EQ(node_.clouds_fused(), 1);
  ASSERT_TRUE(terrain_.Take().has_value()) << LastReason();

  // A mount that is not a pose.
  auto bad_mount = FlatGroundCloud(0, 0.0);
  bad_mount.mount_orientation[0] = nan;
  lcm_.publish(channels::kPointCloud, &bad_mount);
  Run();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(LastReason().find("mount is not finite"), std::string::npos) << LastReason();

  // A base pose that is not a pose.
  auto bad_base = FlatGroundCloud(0, 0.0);
  bad_base.base_orientation[0] = 2.0;
  EXPECT_NE(CheckCloud(bad_base, config_.max_points_per_cloud).value_or("").find("base orientation is not a unit"),
            std::string::npos);

  // A count that disagrees with the points.
  auto bad_count = FlatGroundCloud(0, 0.0);
  bad_count.num_points += 5;
  EXPECT_TRUE(CheckCloud(bad_count, config_.max_points_per_cloud).has_value());

  // More points than the map takes in one cloud (sent in parts, as a large message goes).
  auto huge = FlatGroundCloud(0, 0.0);
  huge.points.assign(static_cast<std::size_t>(config_.max_points_per_cloud) + 1, {1.0f, 0.0f, -0.5f});
  huge.num_points = static_cast<int32_t>(huge.points.size());
  transport::MessagePublisher publisher(lcm_);
  ASSERT_EQ(publisher.Publish(channels::kPointCloud, huge), "");
  Run();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(LastReason().find("more than the map takes"), std::string::npos) << LastReason();

  // A cloud from the future: far ahead of every state heard.
  const auto future = FlatGroundCloud(5000000, 0.0);
  lcm_.publish(channels::kPointCloud, &future);
  Run();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(LastReason().find("after the newest ROBOT_STATE"), std::string::npos) << LastReason();

  // Bytes that are no cloud.
  const std::vector<uint8_t> junk(40, 0xff);
  lcm_.publish(channels::kPointCloud, junk.data(), static_cast<unsigned>(junk.size()));
  Run();
  EXPECT_EQ(status_.Latest()->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_NE(LastReason().find("cannot decode POINT_CLOUD"), std::string::npos) << LastReason();
  EXPECT_EQ(node_.clouds_rejected(), 4);

  // And a good cloud after all that is mapped.
  const auto next_state = State(100000);
  lcm_.publish(channels::kRobotState, &next_state);
  const auto good = FlatGroundCloud(100000, 0.0);
  lcm_.publish(channels::kPointCloud, &good);
  Run();
  EXPECT_EQ(node_.clouds_fused(), 2);
}

TEST_F(TerrainMapperNodeTest, AWaitAtAStepBoundaryGetsTheMapOfItsTime) {
  // Clouds at 0.1 s and 0.2 s; the map goes out at 0.1 s (its period is 0.5 s) but not at 0.2 s.
  for (int64_t t : {100000, 200000}) {
    const auto state = State(t);
    lcm_.publish(channels::kRobotState, &state);
    const auto cloud = FlatGroundCloud(t, 0.0);
    lcm_.publish(channels::kPointCloud, &cloud);
    Run();
  }
  auto terrain = terrain_.Take();
  ASSERT_TRUE(terrain.has_value());
  EXPECT_EQ(terrain->utime, 100000);
  // The robot starts waiting at 0.2 s: the map with every cloud up to then goes out, at that time.
  rbcp_msgs::controller_status_t controller{};
  controller.utime = controller.awaiting_since = 200000;
  controller.awaiting_plan = true;
  lcm_.publish(channels::kControllerStatus, &controller);
  Run();
  terrain = terrain_.Take();
  ASSERT_TRUE(terrain.has_value());
  EXPECT_EQ(terrain->utime, 200000);
  // The same wait again (the controller repeats its status) is no new map.
  lcm_.publish(channels::kControllerStatus, &controller);
  Run();
  EXPECT_FALSE(terrain_.Take().has_value());
}

/// The maps a mapper sent, as (utime, clouds fused) from ELEVATION_MAP.
std::vector<std::pair<int64_t, int64_t>> MapsSent(bool one_step_per_message) {
  lcm::LCM lcm("memq://");
  const RobotModel robot = RobotModel::LoadDefault(kConfig);
  TerrainMapperNode node(lcm, mapping::MapperConfig::LoadFile(kConfig + "/mapper.yaml"), robot);
  node.status().set_verbose(false);
  std::vector<std::pair<int64_t, int64_t>> maps;
  transport::EveryMessage<rbcp_msgs::elevation_map_t> maps_in(
      lcm, channels::kElevationMap, [&](const rbcp_msgs::elevation_map_t& m) { maps.emplace_back(m.utime, m.clouds_fused); },
      nullptr);
  const auto run = [&] {
    for (int i = 0; i < 10; ++i) {
      while (lcm.handleTimeout(0) > 0) {
      }
      if (!node.Step()) break;
    }
  };
  // What the simulator sends from 0.1 s to 0.3 s: each tick's cloud, then its controller status
  // (the robot waits from 0.2 s on), then its state.
  for (int64_t t : {100000, 200000, 300000}) {
    const auto cloud = FlatGroundCloud(t, 0.1 * static_cast<double>(t) / 100000.0);
    lcm.publish(channels::kPointCloud, &cloud);
    rbcp_msgs::controller_status_t controller{};
    controller.utime = t;
    controller.awaiting_plan = t >= 200000;
    controller.awaiting_since = controller.awaiting_plan ? 200000 : 0;
    lcm.publish(channels::kControllerStatus, &controller);
    RobotState s;
    s.t = static_cast<double>(t) * 1e-6;
    s.q = robot.ReferenceConfiguration();
    const auto state = transport::ToRobotStateMsg(s);
    lcm.publish(channels::kRobotState, &state);
    if (one_step_per_message) run();
  }
  run();
  return maps;
}

TEST(TerrainMapperNodeOrder, TheMapsDoNotDependOnHowManyMessagesCameBetweenTwoSteps) {
  const auto one_at_a_time = MapsSent(true);
  ASSERT_EQ(one_at_a_time.size(), 2u);
  EXPECT_EQ(one_at_a_time[1], std::make_pair(int64_t{200000}, int64_t{2})) << "the wait's map has the clouds up to it";
  // A busy mapper hears the three ticks at once: the wait's map still has the clouds heard before
  // the wait, not the one after it.
  EXPECT_EQ(MapsSent(false), one_at_a_time);
}

TEST_F(TerrainMapperNodeTest, ABurstOfCloudsBetweenTwoStepsIsFusedWhole) {
  // The simulator, several times faster than real time, sends a few tens of clouds during one
  // step of a mapper on a loaded machine: every one is fused, none is dropped.
  constexpr int kClouds = 40;
  for (int k = 1; k <= kClouds; ++k) {
    const auto state = State(100000 * k);
    lcm_.publish(channels::kRobotState, &state);
    const auto cloud = FlatGroundCloud(100000 * k, 0.0);
    lcm_.publish(channels::kPointCloud, &cloud);
  }
  Run();
  EXPECT_EQ(node_.clouds_fused(), kClouds);
  EXPECT_EQ(node_.clouds_rejected(), 0);
}

TEST_F(TerrainMapperNodeTest, ACloudThatNeverCameIsCountedAsMissed) {
  for (int64_t t : {100000, 400000}) {  // the captures at 0.2 s and 0.3 s were lost
    const auto cloud = FlatGroundCloud(t, 0.0);
    lcm_.publish(channels::kPointCloud, &cloud);
    const auto state = State(t);
    lcm_.publish(channels::kRobotState, &state);
    Run();
  }
  EXPECT_EQ(node_.clouds_fused(), 2);
  EXPECT_EQ(node_.clouds_missed(), 2);
  rbcp_msgs::controller_status_t controller{};
  controller.utime = controller.awaiting_since = 400000;
  controller.awaiting_plan = true;
  lcm_.publish(channels::kControllerStatus, &controller);
  Run();
  const auto map = map_.Take();
  ASSERT_TRUE(map.has_value());
  EXPECT_EQ(map->clouds_missed, 2);
  EXPECT_NE(LastReason().find("2 never came"), std::string::npos) << LastReason();
}

TEST_F(TerrainMapperNodeTest, ANewRunStartsANewMap) {
  const auto state = State(5000000, 2.0);
  lcm_.publish(channels::kRobotState, &state);
  const auto cloud = FlatGroundCloud(5000000, 2.0);
  lcm_.publish(channels::kPointCloud, &cloud);
  Run();
  ASSERT_TRUE(node_.map().elevation().At(Eigen::Vector2d(3.0, 0.0)).has_value()) << "ahead of the robot";
  // The world's time starts again at 0: a new run.
  const auto restart = State(0, 0.0);
  lcm_.publish(channels::kRobotState, &restart);
  Run();
  EXPECT_EQ(node_.map().elevation().KnownCells(), 0u) << "the old run's map is gone";
}

}  // namespace
}  // namespace rbcp::nodes
