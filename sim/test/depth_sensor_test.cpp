// The simulated depth sensors: the shipped cameras on flat ground from the standing robot (heights,
// ray count, ranges), seeded noise, a box seen at its top, the terrain as it is now, the robot
// invisible to its own sensors, the capture schedule.
#include "rbcp/sim/depth_sensor.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rbcp/core/error.h"
#include "rbcp/sim/sim_config.h"
#include "sim_test_util.h"

namespace rbcp::sim {
namespace {

using test::ConfigDir;
using test::Model;

SensingConfig ShippedSensing() { return SimConfig::LoadFile(ConfigDir() + "/sim.yaml").sensing; }

Eigen::Isometry3d BasePose(const RobotState& s) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = s.base_orientation_W.toRotationMatrix();
  T.translation() = s.base_position_W;
  return T;
}

/// The cloud's points in the world frame, the sensor posed at base_W * mount.
std::vector<Eigen::Vector3d> WorldPoints(const PointCloud& cloud, const Eigen::Isometry3d& base_W) {
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3f& p : cloud.points) points.push_back(base_W * cloud.mount * p.cast<double>());
  return points;
}

/// A 10 x 8 m floor, top at z = 0: larger than the cameras' reach both ways.
std::vector<TerrainElement> Floor() {
  TerrainBox floor;
  floor.size = Eigen::Vector3d(10.0, 8.0, 0.5);
  floor.position = Eigen::Vector3d(0.0, 0.0, -0.25);
  return {floor};
}

/// The robot standing on the floor under a joint PD hold, settled.
class StandingRobot : public ::testing::Test {
 protected:
  void SetUp() override {
    world_.ResetRobot(Eigen::Vector3d(0, 0, Model().NominalBaseHeight() + 0.01), Eigen::Quaterniond::Identity(),
                      Model().ReferenceConfiguration());
    test::RunPdHold(world_, test::StepsFor(world_, 0.5));
  }
  BulletWorld world_{Model(), Floor(), test::ShippedPhysics()};
  SensingConfig sensing_ = ShippedSensing();
};

TEST_F(StandingRobot, TheShippedCamerasSeeTheGroundAtItsHeight) {
  const RobotState state = world_.State();
  const Eigen::Isometry3d base_W = BasePose(state);
  const DepthSensor front("front_camera", 0, sensing_.front_camera, sensing_.range_noise_m, 1);
  const DepthSensor rear("rear_camera", 1, sensing_.rear_camera, sensing_.range_noise_m, 1);
  for (const DepthSensor* sensor : {&front, &rear}) {
    SCOPED_TRACE(sensor->Name());
    const PointCloud cloud = sensor->Capture(world_, base_W, 1, state.t);
    const DepthSensorConfig& c = sensor->Config();
    EXPECT_EQ(cloud.num_rays, c.columns * c.rows);
    EXPECT_EQ(static_cast<int>(sensor->Directions().size()), c.columns * c.rows);
    // The floor fills the image but for its far corners, beyond max_range_m.
    EXPECT_GT(cloud.points.size(), 0.85 * cloud.num_rays);
    EXPECT_LE(static_cast<int>(cloud.points.size()), cloud.num_rays);
    double x_min = 1e9, x_max = -1e9;
    for (const Eigen::Vector3f& p : cloud.points) {
      EXPECT_GE(p.norm(), c.min_range_m - 1e-5);
      EXPECT_LE(p.norm(), c.max_range_m + 1e-5);
      EXPECT_GT(p.x(), 0.0) << "in front of the sensor";
    }
    for (const Eigen::Vector3d& p : WorldPoints(cloud, base_W)) {
      // The noise is along the ray: at most 5 sigma of range, the rays at least 12 deg below the horizon.
      EXPECT_NEAR(p.z(), 0.0, 5.0 * sensing_.range_noise_m);
      const double ahead = (sensor == &front ? 1.0 : -1.0) * p.x();
      x_min = std::min(x_min, ahead);
      x_max = std::max(x_max, ahead);
    }
    // The ground from just ahead of the feet (0.34 m) to about 2.7 m ahead (behind, for the rear one).
    EXPECT_GT(x_min, 0.40);
    EXPECT_LT(x_min, 0.60);
    EXPECT_GT(x_max, 2.5);
  }
}

TEST_F(StandingRobot, WithoutNoiseThePointsLieOnTheGround) {
  const DepthSensor front("front_camera", 0, sensing_.front_camera, 0.0, 1);
  const Eigen::Isometry3d base_W = BasePose(world_.State());
  const PointCloud cloud = front.Capture(world_, base_W, 1, 0.0);
  ASSERT_FALSE(cloud.points.empty());
  for (const Eigen::Vector3d& p : WorldPoints(cloud, base_W)) EXPECT_NEAR(p.z(), 0.0, 1e-5);
}

TEST_F(StandingRobot, TheSameSeedGivesTheSameCloud) {
  const Eigen::Isometry3d base_W = BasePose(world_.State());
  const DepthSensorConfig& c = sensing_.front_camera;
  const DepthSensor a("front_camera", 0, c, 0.01, 7);
  const DepthSensor b("front_camera", 0, c, 0.01, 7);
  const DepthSensor other_seed("front_camera", 0, c, 0.01, 8);
  const DepthSensor other_index("front_camera", 1, c, 0.01, 7);
  const PointCloud first = a.Capture(world_, base_W, 3, 0.0);
  EXPECT_EQ(first.points, a.Capture(world_, base_W, 3, 0.0).points);
  EXPECT_EQ(first.points, b.Capture(world_, base_W, 3, 0.0).points);
  EXPECT_NE(first.points, other_seed.Capture(world_, base_W, 3, 0.0).points);
  EXPECT_NE(first.points, other_index.Capture(world_, base_W, 3, 0.0).points);
  EXPECT_NE(first.points, a.Capture(world_, base_W, 4, 0.0).points) << "each capture draws anew";
}

TEST_F(StandingRobot, ABoxAheadIsSeenAtItsTopAndTheCurrentTerrainIsSeen) {
  const Eigen::Isometry3d base_W = BasePose(world_.State());
  const DepthSensor front("front_camera", 0, sensing_.front_camera, sensing_.range_noise_m, 1);
  TerrainBox box;
  box.size = Eigen::Vector3d(0.4, 0.6, 0.2);
  box.position = Eigen::Vector3d(1.4, 0.0, 0.1);  // top at z = 0.2
  auto on_top = [&](const PointCloud& cloud) {
    int n = 0;
    for (const Eigen::Vector3d& p : WorldPoints(cloud, base_W)) {
      // Inside the box's outline, 3 cm clear of its edges.
      if (std::abs(p.x() - 1.4) < 0.17 && std::abs(p.y()) < 0.27 && p.z() > 0.1) {
        EXPECT_NEAR(p.z(), 0.2, 5.0 * sensing_.range_noise_m);
        ++n;
      }
    }
    return n;
  };
  EXPECT_EQ(on_top(front.Capture(world_, base_W, 1, 0.0)), 0);
  std::vector<TerrainElement> terrain = Floor();
  terrain.push_back(box);
  world_.SetTerrain(terrain);
  EXPECT_GT(on_top(front.Capture(world_, base_W, 2, 0.0)), 20) << "the box added since";
  world_.SetTerrain(Floor());
  EXPECT_EQ(on_top(front.Capture(world_, base_W, 3, 0.0)), 0) << "the box removed since";
}

TEST_F(StandingRobot, TheRobotIsNotInItsOwnClouds) {
  // A sensor 1 m ahead of the base looking back at the robot, and one under the trunk between
  // the legs looking ahead: every ray passes the robot's links to the floor behind them.
  DepthSensorConfig facing = sensing_.front_camera;
  facing.position = Eigen::Vector3d(1.0, 0.0, 0.0);
  facing.rpy = Eigen::Vector3d(0.0, 0.3, M_PI);
  facing.min_range_m = 0.0;
  DepthSensorConfig under = facing;
  under.position = Eigen::Vector3d(0.0, 0.0, -0.1);
  under.rpy = Eigen::Vector3d(0.0, 0.1, 0.0);
  const Eigen::Isometry3d base_W = BasePose(world_.State());
  for (const DepthSensorConfig& c : {facing, under}) {
    const DepthSensor sensor("test", 0, c, 0.0, 1);
    const PointCloud cloud = sensor.Capture(world_, base_W, 1, 0.0);
    ASSERT_FALSE(cloud.points.empty());
    for (const Eigen::Vector3d& p : WorldPoints(cloud, base_W)) EXPECT_NEAR(p.z(), 0.0, 1e-5);
  }
  // The rays through the trunk meet the floor behind it: without the self-filter they would stop
  // at the trunk.
  std::vector<double> distances;
  world_.CastTerrainRays(Eigen::Vector3d(0, 0, 2.0), {-Eigen::Vector3d::UnitZ()}, 5.0, &distances);
  EXPECT_NEAR(distances[0], 2.0, 1e-9);
}

TEST(SensorRig, CapturesEveryRatePeriodOnceWithEveryEnabledSensor) {
  BulletWorld world(Model(), Floor(), test::ShippedPhysics());
  world.ResetRobot(Eigen::Vector3d(0, 0, Model().NominalBaseHeight()), Eigen::Quaterniond::Identity(),
                   Model().ReferenceConfiguration());
  SensingConfig config = ShippedSensing();
  config.rate_hz = 20.0;
  SensorRig rig(config, 400.0);
  EXPECT_EQ(rig.TicksPerCapture(), 20);
  RobotState s = world.State();
  int captures = 0;
  for (int tick = 1; tick <= 200; ++tick) {
    s.t = tick / 400.0;
    const auto clouds = rig.CaptureIfDue(world, s);
    if (clouds.empty()) continue;
    ++captures;
    ASSERT_EQ(clouds.size(), 2u);
    EXPECT_EQ(tick % 20, 0);
    EXPECT_EQ(clouds[0].sensor, "front_camera");
    EXPECT_EQ(clouds[1].sensor, "rear_camera");
    EXPECT_EQ(clouds[0].seq, captures);
    EXPECT_TRUE(rig.CaptureIfDue(world, s).empty()) << "the same tick again: the world stood still";
  }
  EXPECT_EQ(captures, 10);

  config.rear_camera.enabled = false;
  EXPECT_EQ(SensorRig(config, 400.0).Sensors().size(), 1u);
  config.enabled = false;
  EXPECT_TRUE(SensorRig(config, 400.0).Empty());
  config.rate_hz = 30.0;
  EXPECT_THROW(SensorRig(config, 400.0), InputError);
}

TEST(DepthSensor, RejectsABadConfigNamingTheKey) {
  DepthSensorConfig c = DepthSensorConfig::Front();
  c.columns = 0;
  try {
    DepthSensor("front_camera", 0, c, 0.01, 1);
    FAIL() << "zero columns accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'columns'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rbcp::sim
