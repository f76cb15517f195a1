// Root planning over the four benchmark scenarios: 20 seeds each. Reports, per scenario, the
// success count, mean and median planning time, and whether every state sampled every time_step
// along every found path satisfies the reachability condition (checked by an independent checker).
// The `height_field` cases plan over the scenario's terrain as a mapped robot sees it: a height
// field of 4 cm cells (terrain_mapper's resolution), two triangles per cell, which puts many small
// triangles under the trunk.
//
//   build/bin/root_planner_bench [--benchmark_filter=darpa]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/root_planner.h"
#include "rbcp/scenario/scenario.h"

namespace {

using namespace rbcp;

const std::string kConfigDir = std::string(RBCP_SOURCE_DIR) + "/config";
constexpr int kSeeds = 20;
constexpr double kBudgetSeconds = 10.0;
constexpr double kMapCell = 0.04;  // [m]

// The terrain's highest points on a grid of `cell` [m] over its xy bounds, as a mesh of two
// triangles per cell (cells with a corner off the terrain are left out).
TriangleMesh HeightField(const TriangleMesh& terrain, double cell) {
  const TerrainHeightMap heights(terrain);
  Eigen::Vector2d lo = terrain.vertices.front().head<2>(), hi = lo;
  for (const auto& v : terrain.vertices) {
    lo = lo.cwiseMin(v.head<2>());
    hi = hi.cwiseMax(v.head<2>());
  }
  const int nx = static_cast<int>((hi.x() - lo.x()) / cell) + 1;
  const int ny = static_cast<int>((hi.y() - lo.y()) / cell) + 1;
  TriangleMesh mesh;
  std::vector<int> index(static_cast<std::size_t>(nx * ny), -1);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector2d xy = lo + cell * Eigen::Vector2d(i, j);
      if (const auto z = heights.At(xy)) {
        index[static_cast<std::size_t>(j * nx + i)] = static_cast<int>(mesh.vertices.size());
        mesh.vertices.emplace_back(xy.x(), xy.y(), *z);
      }
    }
  }
  const auto at = [&](int i, int j) { return index[static_cast<std::size_t>(j * nx + i)]; };
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (a < 0 || b < 0 || c < 0 || d < 0) continue;
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  }
  return mesh;
}

void BM_RootPlan(benchmark::State& state, const std::string& scenario_name, bool height_field) {
  const RobotModel robot = RobotModel::LoadDefault(kConfigDir);
  const RootPlanner planner(robot, RootPlannerConfig::LoadFile(kConfigDir + "/root_planner.yaml", kConfigDir));
  Scenario scenario = LoadScenario(kConfigDir + "/scenarios/" + scenario_name + ".yaml");
  if (height_field) scenario.terrain_mesh = HeightField(scenario.terrain_mesh, kMapCell);
  AffordanceExtractor extractor(AffordanceConfig::LoadFile(kConfigDir + "/affordance.yaml"));
  const std::vector<AffordanceSurface> surfaces = extractor.Extract(scenario.terrain_mesh);
  const auto start = planner.StandingPosition(scenario.terrain_mesh, scenario.start.position);
  const auto goal = planner.StandingPosition(scenario.terrain_mesh, scenario.goal.position);
  if (!start || !goal) {
    state.SkipWithError("no terrain below start or goal");
    return;
  }
  ReachabilityChecker verifier = planner.MakeChecker(scenario.terrain_mesh, surfaces);

  std::vector<double> times;
  std::vector<double> durations;
  int successes = 0;
  int verified = 0;
  long samples = 0;
  long checks = 0;
  unsigned seed = 0;
  for (auto _ : state) {
    times.clear();
    durations.clear();
    successes = verified = 0;
    samples = checks = 0;
    for (int i = 0; i < kSeeds; ++i) {
      seed = static_cast<unsigned>(i + 1);
      const RootPlanResult result = planner.Plan(scenario.terrain_mesh, surfaces, *start, scenario.start.yaw, *goal,
                                                 scenario.goal.yaw, seed, kBudgetSeconds);
      times.push_back(result.planning_time_s);
      checks += result.validity_checks;
      if (!result.ok()) continue;
      ++successes;
      durations.push_back(result.path.Duration());
      bool all_valid = true;
      for (const auto& s : result.samples) all_valid = verifier.IsValid(s.p, s.yaw) && all_valid;
      samples += static_cast<long>(result.samples.size());
      if (all_valid) ++verified;
    }
  }
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  const double mean = std::accumulate(times.begin(), times.end(), 0.0) / static_cast<double>(times.size());
  const double median = 0.5 * (sorted[(sorted.size() - 1) / 2] + sorted[sorted.size() / 2]);
  state.counters["seeds"] = kSeeds;
  state.counters["success"] = successes;
  state.counters["verified"] = verified;
  state.counters["mean_s"] = mean;
  state.counters["median_s"] = median;
  state.counters["max_s"] = sorted.back();
  state.counters["mean_path_s"] =
      durations.empty() ? 0.0 : std::accumulate(durations.begin(), durations.end(), 0.0) / static_cast<double>(durations.size());
  state.counters["samples"] = static_cast<double>(samples);
  state.counters["checks_per_plan"] = static_cast<double>(checks) / kSeeds;
}

BENCHMARK_CAPTURE(BM_RootPlan, flat_ground, std::string("flat_ground"), false)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RootPlan, slalom_debris, std::string("slalom_debris"), false)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RootPlan, plinth, std::string("plinth"), false)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RootPlan, darpa_rubble, std::string("darpa_rubble"), false)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RootPlan, plinth_height_field, std::string("plinth"), true)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RootPlan, darpa_rubble_height_field, std::string("darpa_rubble"), true)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
