// Speed of the simulated world: simulated seconds per wall-clock second (the `sim_s_per_s`
// counter) of ANYmal B standing on flat ground under a joint PD hold, with the shipped physics
// (config/sim.yaml). The controller runs at 400 Hz (every third 1/1200 s step: State(), then
// SetJointTorques()), as the simulator process drives it, or in every step. And the cost of one
// capture of the front depth camera (config/sim.yaml `sensing:`) on the DARPA rubble terrains.

#include <benchmark/benchmark.h>

#include "rbcp/core/yaml_reader.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/sim/bullet_world.h"
#include "rbcp/sim/depth_sensor.h"

namespace {

const std::string kConfig = std::string(RBCP_SOURCE_DIR) + "/config";

const rbcp::RobotModel& Model() {
  static const rbcp::RobotModel model = rbcp::RobotModel::LoadDefault(kConfig);
  return model;
}

std::unique_ptr<rbcp::sim::BulletWorld> StandingWorld() {
  const auto physics = rbcp::sim::PhysicsConfig::Load(rbcp::YamlMap::LoadFile(kConfig + "/sim.yaml").Map("physics"));
  rbcp::TerrainBox floor;
  floor.size = Eigen::Vector3d(5.0, 3.0, 0.5);
  floor.position = Eigen::Vector3d(0.75, 0.0, -0.25);
  auto world = std::make_unique<rbcp::sim::BulletWorld>(Model(), std::vector<rbcp::TerrainElement>{floor}, physics);
  world->ResetRobot(Eigen::Vector3d(0, 0, Model().NominalBaseHeight() + 0.01), Eigen::Quaterniond::Identity(),
                    Model().ReferenceConfiguration());
  return world;
}

void Hold(rbcp::sim::BulletWorld& world) {
  const rbcp::RobotState s = world.State();
  world.SetJointTorques(200.0 * (Model().ReferenceConfiguration() - s.q) - 5.0 * s.qd);
}

/// One benchmark iteration = one simulated second.
void BM_PdStanding400Hz(benchmark::State& state) {
  auto world = StandingWorld();
  const int steps = static_cast<int>(std::lround(1.0 / world->Config().time_step_s));
  for (int k = 0; k < steps; ++k) {  // settle first
    if (k % 3 == 0) Hold(*world);
    world->Step();
  }
  for (auto _ : state) {
    for (int k = 0; k < steps; ++k) {
      if (k % 3 == 0) Hold(*world);
      world->Step();
    }
  }
  state.counters["sim_s_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PdStanding400Hz)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The same with the PD updated in every step (State() each step).
void BM_PdStanding1200Hz(benchmark::State& state) {
  auto world = StandingWorld();
  const int steps = static_cast<int>(std::lround(1.0 / world->Config().time_step_s));
  for (int k = 0; k < steps; ++k) {
    Hold(*world);
    world->Step();
  }
  for (auto _ : state) {
    for (int k = 0; k < steps; ++k) {
      Hold(*world);
      world->Step();
    }
  }
  state.counters["sim_s_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PdStanding1200Hz)->Unit(benchmark::kMillisecond)->UseRealTime();

/// One iteration = one capture of the front camera (shipped config), the robot standing at the
/// scenario's start at its nominal height above the terrain there, facing the rubble.
void BM_FrontCameraCapture(benchmark::State& state, const std::string& scenario_name) {
  const auto physics = rbcp::sim::PhysicsConfig::Load(rbcp::YamlMap::LoadFile(kConfig + "/sim.yaml").Map("physics"));
  const rbcp::YamlMap sensing_map = rbcp::YamlMap::LoadFile(kConfig + "/sim.yaml").Map("sensing");
  const auto sensing = rbcp::LoadConfig<rbcp::sim::SensingConfig>(sensing_map);
  const rbcp::Scenario scenario = rbcp::LoadScenario(kConfig + "/scenarios/" + scenario_name + ".yaml");
  rbcp::sim::BulletWorld world(Model(), scenario.terrain, physics);
  // The terrain's height under the start, by a ray straight down.
  std::vector<double> down;
  const Eigen::Vector3d above(scenario.start.position.x(), scenario.start.position.y(), 5.0);
  world.CastTerrainRays(above, {-Eigen::Vector3d::UnitZ()}, 10.0, &down);
  Eigen::Isometry3d base_W = Eigen::Isometry3d::Identity();
  base_W.linear() = Eigen::AngleAxisd(scenario.start.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  base_W.translation() = above - Eigen::Vector3d::UnitZ() * (down[0] - Model().NominalBaseHeight());
  const rbcp::sim::DepthSensor camera("front_camera", 0, sensing.front_camera, sensing.range_noise_m, sensing.noise_seed);
  int64_t seq = 0;
  std::size_t points = 0;
  for (auto _ : state) {
    const rbcp::sim::PointCloud cloud = camera.Capture(world, base_W, ++seq, 0.0);
    points = cloud.points.size();
    benchmark::DoNotOptimize(cloud.points.data());
  }
  state.counters["rays"] = static_cast<double>(camera.Directions().size());
  state.counters["points"] = static_cast<double>(points);
}
BENCHMARK_CAPTURE(BM_FrontCameraCapture, darpa_rubble, std::string("darpa_rubble"))->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_FrontCameraCapture, paper_darpa, std::string("paper_darpa"))->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
