// Speed of the simulated world: simulated seconds per wall-clock second (the `sim_s_per_s`
// counter) of ANYmal B standing on flat ground under a joint PD hold, with the shipped physics
// (config/sim.yaml). The controller runs at 400 Hz (every third 1/1200 s step: State(), then
// SetJointTorques()), as the simulator process drives it, or in every step.

#include <benchmark/benchmark.h>

#include "rbcp/core/yaml_reader.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/sim/bullet_world.h"

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

}  // namespace

BENCHMARK_MAIN();
