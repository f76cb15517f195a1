// Collision query speed on the DARPA rubble terrain over a fixed seeded set of stance poses along
// the start-goal line (four feet on the terrain by IK): one stance leg (the foothold-candidate
// path), the whole robot, the robot lifted clear of the terrain, and self-collision of joint
// vectors sampled inside the planning bounds. "collide" is the fraction of queries in collision.
//
//   build/bin/collision_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "rbcp/collision/robot_terrain_collision.h"
#include "rbcp/core/pose.h"
#include "rbcp/scenario/scenario.h"

namespace {

using namespace rbcp;

const std::string kConfigDir = std::string(RBCP_SOURCE_DIR) + "/config";
constexpr int kQueries = 512;
constexpr unsigned kSeed = 7;

struct Query {
  Eigen::Isometry3d base_W = Eigen::Isometry3d::Identity();
  JointVector q = JointVector::Zero();
  Leg leg = Leg::kLF;
};

struct Fixture {
  RobotModel robot;
  Scenario scenario;
  RobotTerrainCollision checker;  // default options: penetration measured
  RobotTerrainCollision yes_no;   // measure_penetration = false
  std::vector<Query> queries;
  std::vector<JointVector> sampled_joints;

  static CollisionOptions YesNo() {
    CollisionOptions options;
    options.measure_penetration = false;
    return options;
  }

  Fixture()
      : robot(RobotModel::LoadDefault(kConfigDir)),
        scenario(LoadScenario(kConfigDir + "/scenarios/darpa_rubble.yaml")),
        checker(robot, scenario.terrain_mesh),
        yes_no(robot, scenario.terrain_mesh, YesNo()) {
    // Stance poses: the base along the start-goal line, each foot on the terrain near its
    // reference position (IK), the base at the nominal height above the mean foot height.
    std::mt19937 rng(kSeed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Eigen::Vector2d start = scenario.start.position, goal = scenario.goal.position;
    while (static_cast<int>(queries.size()) < kQueries) {
      Query query;
      const Eigen::Vector2d xy = start + unit(rng) * (goal - start) + Eigen::Vector2d(0.0, 0.2 * unit(rng) - 0.1);
      const double yaw = 0.3 * unit(rng) - 0.15;
      const Eigen::Matrix3d R = RotationFromRpy(Eigen::Vector3d(0.0, 0.0, yaw));
      std::array<Eigen::Vector3d, kNumLegs> feet_W;
      bool on_ground = true;
      double mean_z = 0.0;
      for (Leg leg : kAllLegs) {
        const Eigen::Vector3d offset = robot.ReferenceFootPosition(leg) + Eigen::Vector3d(0.16 * unit(rng) - 0.08, 0.08 * unit(rng) - 0.04, 0.0);
        const Eigen::Vector2d foot_xy = xy + (R * offset).head<2>();
        const auto ground = TerrainHeightAt(scenario.terrain_mesh, foot_xy);
        if (!ground) on_ground = false;
        feet_W[static_cast<std::size_t>(Index(leg))] << foot_xy, ground.value_or(0.0);
        mean_z += ground.value_or(0.0) / kNumLegs;
      }
      if (!on_ground) continue;
      query.base_W.linear() = R;
      query.base_W.translation() << xy, mean_z + robot.NominalBaseHeight() - 0.04 * unit(rng);
      bool reachable = true;
      for (Leg leg : kAllLegs) {
        const IkResult ik = robot.SolveLegIk(leg, query.base_W.inverse() * feet_W[static_cast<std::size_t>(Index(leg))]);
        reachable = reachable && ik.ok();
        SetLegJoints(query.q, leg, ik.q);
      }
      if (!reachable) continue;
      query.leg = kAllLegs[queries.size() % kNumLegs];
      queries.push_back(query);
    }
    // Joint vectors drawn inside the planning bounds, as a limb database samples them.
    for (int i = 0; i < kQueries; ++i) {
      JointVector q;
      for (int j = 0; j < kNumJoints; ++j) {
        q[j] = robot.JointLowerBounds()[j] + unit(rng) * (robot.JointUpperBounds()[j] - robot.JointLowerBounds()[j]);
      }
      sampled_joints.push_back(q);
    }
  }
};

const Fixture& GetFixture() {
  static const Fixture fixture;
  return fixture;
}

// state.range(0): 1 = penetration measured (default options), 0 = yes/no only.
const RobotTerrainCollision& Checker(const benchmark::State& state) {
  return state.range(0) != 0 ? GetFixture().checker : GetFixture().yes_no;
}

void BM_CheckLeg(benchmark::State& state) {
  const Fixture& f = GetFixture();
  const RobotTerrainCollision& checker = Checker(state);
  std::size_t i = 0;
  long collide = 0;
  for (auto _ : state) {
    const Query& query = f.queries[i++ % f.queries.size()];
    const CollisionReport report = checker.CheckLeg(query.leg, query.base_W, LegJoints(query.q, query.leg), true);
    collide += report.collision ? 1 : 0;
    benchmark::DoNotOptimize(report);
  }
  state.counters["collide"] = static_cast<double>(collide) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_CheckLeg)->ArgName("depth")->Arg(1)->Arg(0);

void BM_CheckRobot(benchmark::State& state) {
  const Fixture& f = GetFixture();
  const RobotTerrainCollision& checker = Checker(state);
  std::size_t i = 0;
  long collide = 0;
  for (auto _ : state) {
    const Query& query = f.queries[i++ % f.queries.size()];
    const CollisionReport report = checker.CheckRobot(query.base_W, query.q, {true, true, true, true});
    collide += report.collision ? 1 : 0;
    benchmark::DoNotOptimize(report);
  }
  state.counters["collide"] = static_cast<double>(collide) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_CheckRobot)->ArgName("depth")->Arg(1)->Arg(0);

// The whole robot lifted 1 m above its query pose: nothing touches, every shape is tested.
void BM_CheckRobotFree(benchmark::State& state) {
  const Fixture& f = GetFixture();
  std::size_t i = 0;
  long collide = 0;
  for (auto _ : state) {
    const Query& query = f.queries[i++ % f.queries.size()];
    Eigen::Isometry3d base = query.base_W;
    base.translation().z() += 1.0;
    const CollisionReport report = f.checker.CheckRobot(base, query.q, {false, false, false, false});
    collide += report.collision ? 1 : 0;
    benchmark::DoNotOptimize(report);
  }
  state.counters["collide"] = static_cast<double>(collide) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_CheckRobotFree);

void BM_CheckSelf(benchmark::State& state) {
  const Fixture& f = GetFixture();
  std::size_t i = 0;
  long collide = 0;
  for (auto _ : state) {
    const CollisionReport report = f.checker.CheckSelf(f.sampled_joints[i++ % f.sampled_joints.size()]);
    collide += report.collision ? 1 : 0;
    benchmark::DoNotOptimize(report);
  }
  state.counters["collide"] = static_cast<double>(collide) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_CheckSelf);

}  // namespace

BENCHMARK_MAIN();
