// Contact planning time per scenario over 20 seeds. The root paths are planned once per scenario
// and seed before timing; each benchmark iteration plans the contacts of every path. Counters:
// successes (of the seeds with a root path), checked (successes whose plan passes the independent
// plan checker, run outside the timed part), mean / median / max planning time [s], mean steps
// (after step merging; mean_merged: the steps merging removed), mean step length (distance the
// stepping foot moves) [m] and steps per metre of root path.
// The limb database uses config/limb_database.yaml (50,000 samples per leg, cached on disk).
// RBCP_BENCH_PATHS=1 also prints each path's outcome, planning time, evaluations and steps to stderr.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/contact_planner/contact_planner.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/plan_checker/plan_checker.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/root_planner.h"
#include "rbcp/scenario/scenario.h"

namespace {

using namespace rbcp;

// RBCP_CONFIG_DIR overrides the configuration folder (to compare parameter sets).
const bool kPrintPaths = std::getenv("RBCP_BENCH_PATHS") != nullptr;
const std::string kConfigDir =
    std::getenv("RBCP_CONFIG_DIR") ? std::string(std::getenv("RBCP_CONFIG_DIR")) : std::string(RBCP_SOURCE_DIR) + "/config";
constexpr unsigned kSeeds = 20;

const RobotModel& Robot() {
  static const RobotModel robot = RobotModel::LoadDefault(kConfigDir);
  return robot;
}

const LimbDatabase& Database() {
  static const LimbDatabase db =
      LimbDatabase::LoadOrBuild(Robot(), LimbDatabase::DefaultRobotFiles(kConfigDir),
                                LimbDatabaseConfig::LoadFile(kConfigDir + "/limb_database.yaml"));
  return db;
}

struct Prepared {
  Scenario scenario;
  std::vector<AffordanceSurface> surfaces;
  std::vector<std::vector<RootPathSample>> paths;  ///< one per seed with a root path
};

const Prepared& Prepare(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Prepared>> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return *it->second;
  auto p = std::make_unique<Prepared>();
  p->scenario = LoadScenario(kConfigDir + "/scenarios/" + name + ".yaml");
  AffordanceExtractor extractor(AffordanceConfig::Load(YamlMap::LoadFile(kConfigDir + "/affordance.yaml")));
  p->surfaces = extractor.Extract(p->scenario.terrain_mesh);
  const RootPlanner planner(Robot(), RootPlannerConfig::LoadFile(kConfigDir + "/root_planner.yaml", kConfigDir));
  const auto start = planner.StandingPosition(p->scenario.terrain_mesh, p->scenario.start.position);
  const auto goal = planner.StandingPosition(p->scenario.terrain_mesh, p->scenario.goal.position);
  for (unsigned seed = 1; seed <= kSeeds && start && goal; ++seed) {
    const RootPlanResult r = planner.Plan(p->scenario.terrain_mesh, p->surfaces, *start, p->scenario.start.yaw, *goal,
                                          p->scenario.goal.yaw, seed, 20.0);
    if (r.ok()) p->paths.push_back(r.path.SampleEvery(0.01));
  }
  return *cache.emplace(name, std::move(p)).first->second;
}

void BM_ContactPlan(benchmark::State& state, const std::string& name) {
  const Prepared& prepared = Prepare(name);
  ContactPlanner planner(Robot(), Database(), EquilibriumConfig::LoadFile(kConfigDir + "/equilibrium.yaml"),
                         ContactPlannerConfig::LoadFile(kConfigDir + "/contact_planner.yaml"),
                         StanceConfig::LoadFile(kConfigDir + "/stance.yaml"));
  planner.SetTerrain(prepared.scenario.terrain_mesh, prepared.surfaces);
  std::vector<double> times;
  std::vector<ContactPlan> plans;
  int successes = 0;
  double steps = 0.0;
  double merged = 0.0;       // steps removed by step merging, over the plans found
  double path_length = 0.0;  // of the planned paths [m]
  double evaluations = 0.0;  // leg evaluations over all queries (the search's bound)
  double max_evaluations = 0.0;
  for (auto _ : state) {
    evaluations = 0.0;
    max_evaluations = 0.0;
    times.clear();
    plans.clear();
    successes = 0;
    steps = 0.0;
    merged = 0.0;
    path_length = 0.0;
    for (std::size_t i = 0; i < prepared.paths.size(); ++i) {
      const ContactPlanResult r = planner.Plan(prepared.paths[i]);
      times.push_back(r.planning_time_s);
      const auto path_evaluations = r.stats.Evaluations();
      const double e = static_cast<double>(path_evaluations);
      evaluations += e;
      max_evaluations = std::max(max_evaluations, e);
      if (kPrintPaths) {
        std::cerr << name << " path " << i << ": " << (r.ok ? "ok" : "failed") << ", " << r.planning_time_s << " s, "
                  << path_evaluations << " evaluations (" << r.stats.keep_checks << " keep checks, "
                  << r.stats.candidates_evaluated << " footholds of " << r.stats.candidates << " candidates in "
                  << r.stats.step_attempts << " step attempts), " << r.stats.stability_evaluations
                  << " stability evaluations, " << r.stats.swing_checks << " swing checks, "
                  << r.stats.backtracks << " backtracks, " << r.steps << " steps\n";
      }
      if (r.ok) {
        ++successes;
        steps += r.steps;
        merged += r.stats.steps_merged;
        plans.push_back(r.plan);
        const std::vector<RootPathSample>& path = prepared.paths[i];
        for (std::size_t k = 1; k < path.size(); ++k) path_length += (path[k].p - path[k - 1].p).head<2>().norm();
      } else {
        std::cerr << name << " path " << i << ": " << r.reason << "\n";
      }
    }
  }
  int checked = 0;
  for (const ContactPlan& plan : plans) {
    const PlanCheckReport report = CheckPlanForScenario(kConfigDir, prepared.scenario, plan);
    if (report.ok) ++checked;
    else std::cerr << name << ": " << report.Summary() << "\n";
  }
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  double mean = 0.0;
  for (double t : times) mean += t;
  mean /= std::max<std::size_t>(1, times.size());
  state.counters["root_paths"] = static_cast<double>(prepared.paths.size());
  state.counters["successes"] = successes;
  state.counters["checked"] = checked;
  state.counters["mean_s"] = mean;
  state.counters["median_s"] = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  state.counters["max_s"] = sorted.empty() ? 0.0 : sorted.back();
  state.counters["mean_steps"] = successes > 0 ? steps / successes : 0.0;
  state.counters["mean_merged"] = successes > 0 ? merged / successes : 0.0;
  double moved = 0.0;
  int moves = 0;
  for (const ContactPlan& plan : plans) {
    for (std::size_t k = 1; k < plan.states.size(); ++k) {
      const int leg = plan.states[k].moving_leg;
      if (leg < 0 || leg >= kNumLegs) continue;
      const auto l = static_cast<std::size_t>(leg);
      moved += (plan.states[k].feet[l].position - plan.states[k - 1].feet[l].position).norm();
      ++moves;
    }
  }
  state.counters["step_length_m"] = moves > 0 ? moved / moves : 0.0;
  state.counters["steps_per_m"] = path_length > 0.0 ? steps / path_length : 0.0;
  state.counters["mean_evaluations"] = evaluations / std::max<double>(1.0, static_cast<double>(prepared.paths.size()));
  state.counters["max_evaluations"] = max_evaluations;
}

/// Timing a whole plan for the dynamic walk and checking its walk (ContactPlanner::TimeWalk, part
/// of every Plan above): per plan, and the steps it slowed or found failing, over seed 1's plan.
void BM_TimeDynamicWalk(benchmark::State& state, const std::string& name) {
  const Prepared& prepared = Prepare(name);
  ContactPlanner planner(Robot(), Database(), EquilibriumConfig::LoadFile(kConfigDir + "/equilibrium.yaml"),
                         ContactPlannerConfig::LoadFile(kConfigDir + "/contact_planner.yaml"),
                         StanceConfig::LoadFile(kConfigDir + "/stance.yaml"));
  planner.SetTerrain(prepared.scenario.terrain_mesh, prepared.surfaces);
  if (prepared.paths.empty()) {
    state.SkipWithError("no root path");
    return;
  }
  const ContactPlanResult r = planner.Plan(prepared.paths.front());
  if (!r.ok) {
    state.SkipWithError(r.reason.c_str());
    return;
  }
  ContactPlanStats stats;
  for (auto _ : state) {
    ContactPlan plan = r.plan;
    stats = ContactPlanStats{};
    planner.TimeWalk(&plan, &stats);
    benchmark::DoNotOptimize(plan.states.back().touch_down_s);
  }
  state.counters["steps"] = r.steps;
  state.counters["per_step"] = benchmark::Counter(static_cast<double>(state.iterations()) * r.steps,
                                                  benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["steps_slowed"] = stats.walk_steps_slowed;
  state.counters["steps_failing"] = stats.walk_steps_failing;
}

BENCHMARK_CAPTURE(BM_TimeDynamicWalk, flat_ground, std::string("flat_ground"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TimeDynamicWalk, darpa_rubble, std::string("darpa_rubble"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TimeDynamicWalk, paper_plinth, std::string("paper_plinth"))->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(BM_ContactPlan, flat_ground, std::string("flat_ground"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ContactPlan, slalom_debris, std::string("slalom_debris"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ContactPlan, plinth, std::string("plinth"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ContactPlan, darpa_rubble, std::string("darpa_rubble"))->Unit(benchmark::kMillisecond)->Iterations(1);
// The paper's own terrain meshes.
BENCHMARK_CAPTURE(BM_ContactPlan, paper_flat_ground, std::string("paper_flat_ground"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ContactPlan, paper_slalom_debris, std::string("paper_slalom_debris"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ContactPlan, paper_plinth, std::string("paper_plinth"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ContactPlan, paper_darpa, std::string("paper_darpa"))->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
