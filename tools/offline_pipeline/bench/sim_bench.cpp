// sim_bench: the paper's yardstick, success in dynamic simulation. For every scenario and seed it
// plans (affordances, root path, contacts; the next guide when no contact plan follows a root
// path), checks the plan with the plan checker and walks it in the simulator, in parallel jobs,
// and prints per scenario: plans, those planned along a later guide, plans passing the checker,
// goals reached, the failures by kind, mean simulated time to the goal, mean speed, mean step period
// (simulated time over steps), steps, and the real-time factor of the simulation with the
// controller in the loop (median over runs). Markdown on stdout; --json FILE also writes every
// run. By default the box scenarios and the paper's meshes.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "rbcp/core/format.h"
#include "rbcp/core/run_metrics.h"
#include "rbcp/offline_pipeline/offline_pipeline.h"
#include "rbcp/cli/cli.h"
#include "rbcp/plan_checker/plan_checker.h"

namespace {

using namespace rbcp;

struct Run {
  std::string scenario;
  unsigned seed = 0;
  bool planned = false;
  bool checked = false;  // the plan passes check_plan
  bool reached = false;
  std::string failure;  // "" or what failed ("contact", "fall", ...)
  std::string detail;
  int steps = 0;
  int guides = 0;  // root paths planned (more than one when no contact plan followed the first)
  double sim_s = 0.0, wall_s = 0.0, max_torque_ratio = 0.0;
  Eigen::Vector2d start_xy = Eigen::Vector2d::Zero(), end_xy = Eigen::Vector2d::Zero();  ///< the base, walked
  int collisions = 0;
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The command line.
struct Options {
  std::string config_dir = DefaultConfigDir();
  std::string json_path;
  std::vector<std::string> scenarios = {"flat_ground",       "slalom_debris",       "plinth",       "darpa_rubble",
                                        "paper_flat_ground", "paper_slalom_debris", "paper_plinth", "paper_darpa"};
  unsigned seeds = 20;
  unsigned first_seed = 1;
  int jobs = 2;
  double budget = 5.0;
  std::string walk;  // controller.yaml's mode when empty
};

void AddOptions(CLI::App& app, Options& o) {
  app.add_option("--config-dir", o.config_dir, "configuration folder")->capture_default_str();
  app.add_option("--scenarios", o.scenarios, "scenario names (config/scenarios/NAME.yaml) or files")->capture_default_str();
  app.add_option("--seeds", o.seeds, "seeds per scenario")->capture_default_str();
  app.add_option("--first-seed", o.first_seed, "first seed")->capture_default_str();
  app.add_option("--jobs", o.jobs, "runs in parallel")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--time-budget", o.budget, "root planning time budget [s]")->capture_default_str();
  app.add_option("--json", o.json_path, "also write every run to this JSON file");
  app.add_option("--walk", o.walk, "how the controller walks: static or dynamic (default: controller.yaml's mode)")
      ->check(CLI::IsMember({"static", "dynamic"}));
  app.description("Plans and simulates every scenario over several seeds; prints the success table. Talks no LCM.");
}

/// Each of --scenarios: a name (CONFIG_DIR/scenarios/NAME.yaml) or a file.
std::vector<Scenario> LoadScenarios(const Options& o) {
  std::vector<Scenario> loaded;
  for (const std::string& s : o.scenarios) {
    loaded.push_back(LoadScenario(s.find('/') == std::string::npos && s.find(".yaml") == std::string::npos
                                      ? o.config_dir + "/scenarios/" + s + ".yaml"
                                      : s));
  }
  return loaded;
}

/// Every scenario with every seed, run in parallel jobs.
class Bench {
 public:
  /// Loads the pipeline (and the limb database), then the scenarios.
  explicit Bench(const Options& o) : o_(o), pipeline_(o.config_dir) {
    // Runs in parallel share the cores with the contact planner's own search threads.
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    if (o_.jobs > 1) pipeline_.SetContactSearchThreads(std::max(1, cores / o_.jobs));
    if (!o_.walk.empty()) pipeline_.SetWalkMode(*ValueOf(o_.walk, WalkModeNames()));  // --walk checked it
    pipeline_.limb_database();
    scenarios_ = LoadScenarios(o_);
  }

  const std::vector<Scenario>& scenarios() const { return scenarios_; }

  /// The runs, scenario by scenario, seed by seed.
  std::vector<Run> RunAll() {
    std::vector<std::pair<std::size_t, unsigned>> work;
    for (std::size_t i = 0; i < scenarios_.size(); ++i) {
      for (unsigned k = 0; k < o_.seeds; ++k) work.emplace_back(i, o_.first_seed + k);
    }
    std::vector<Run> runs(work.size());
    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
      for (std::size_t w = next++; w < work.size(); w = next++) runs[w] = RunOne(scenarios_[work[w].first], work[w].second);
    };
    std::vector<std::thread> threads;
    for (int j = 0; j < o_.jobs; ++j) threads.emplace_back(worker);
    for (std::thread& t : threads) t.join();
    return runs;
  }

 private:
  /// A line on stderr, whole among the jobs' lines.
  void Say(const std::string& line) {
    std::lock_guard<std::mutex> lock(print_);
    std::cerr << "sim_bench: " << line << "\n";
  }

  /// Plans, checks and walks the scenario with the seed.
  Run RunOne(const Scenario& scenario, unsigned seed) {
    Run run;
    run.scenario = scenario.name;
    run.seed = seed;
    const std::string name = run.scenario + " seed " + std::to_string(seed);
    PipelineResult r;
    try {
      r = pipeline_.Run(scenario, PipelineStage::kSim, seed, o_.budget);
    } catch (const std::exception& e) {
      // A run that cannot even start (bad input, a configuration error) is a failed run.
      run.failure = "error";
      run.detail = e.what();
      Say(name + ": FAILED " + run.detail);
      return run;
    }
    run.planned = r.contact && r.contact->ok;
    run.guides = r.root ? static_cast<int>(r.failed_guides.size()) + 1 : 0;
    run.steps = run.planned ? r.contact->steps : 0;
    if (run.planned) {
      try {
        const PlanCheckReport check = CheckPlanForScenario(o_.config_dir, scenario, r.contact->plan);
        run.checked = check.ok;
        if (!check.ok) Say(name + ": check_plan: " + check.Summary());
      } catch (const std::exception& e) {
        // The checker reads the configuration again: a file changed or broken since the start.
        run.failure = "error";
        run.detail = std::string("check_plan: ") + e.what();
        Say(name + ": FAILED " + run.detail);
        return run;
      }
    }
    TakeWalk(r, run);
    Say(name + ": " + (run.reached ? "goal reached" : "FAILED " + run.detail) + " (" + std::to_string(run.steps) +
        " steps, " + FixedNumber(run.sim_s, 1) + " s simulated in " + FixedNumber(run.wall_s, 1) + " s)");
    return run;
  }

  /// The simulator's figures of the walk, or the stage that failed before it.
  static void TakeWalk(const PipelineResult& r, Run& run) {
    if (!r.sim) {
      run.failure = r.contact ? "contact" : r.root ? "root" : "affordance";
      run.detail = r.failure;
      return;
    }
    run.reached = r.sim->ok();
    run.sim_s = r.sim->sim_time_s;
    run.wall_s = r.sim_wall_s;
    run.max_torque_ratio = r.sim->max_torque_ratio;
    run.collisions = r.sim->collisions;
    if (!r.sim->trace.empty()) {
      run.start_xy = r.sim->trace.front().base_position.head<2>();
      run.end_xy = r.sim->trace.back().base_position.head<2>();
    }
    if (r.sim->failure) {
      run.failure = r.sim->failure->what;
      run.detail = r.failure;
    }
  }

  const Options& o_;
  OfflinePipeline pipeline_;
  std::vector<Scenario> scenarios_;
  std::mutex print_;
};

nlohmann::json RunJson(const Run& r) {
  return {{"scenario", r.scenario}, {"seed", r.seed}, {"planned", r.planned}, {"checked", r.checked},
          {"reached_goal", r.reached},
          {"failure", r.failure.empty() ? nlohmann::json() : nlohmann::json(r.failure)},
          {"detail", r.detail}, {"guides", r.guides}, {"steps", r.steps}, {"sim_time_s", r.sim_s}, {"sim_wall_s", r.wall_s},
          {"distance_m", (r.end_xy - r.start_xy).norm()}, {"max_torque_ratio", r.max_torque_ratio},
          {"collisions", r.collisions}};
}

/// The table's row of a scenario, over its runs.
void PrintRow(const Scenario& scenario, const std::vector<Run>& runs, unsigned seeds) {
  int planned = 0, checked = 0, reached = 0, later_guide = 0;
  double time = 0.0, speed = 0.0, period = 0.0, steps = 0.0, torque = 0.0;
  std::vector<double> rtf;
  std::map<std::string, int> failures;
  for (const Run& r : runs) {
    if (r.scenario != scenario.name) continue;
    planned += r.planned;
    later_guide += r.planned && r.guides > 1;
    checked += r.checked;
    if (r.planned) steps += r.steps;
    if (r.wall_s > 0.0) rtf.push_back(r.sim_s / r.wall_s);
    torque = std::max(torque, r.max_torque_ratio);
    if (r.reached) {
      ++reached;
      time += r.sim_s;
      speed += RunSpeedMps(r.start_xy, r.end_xy, r.sim_s);
      period += StepPeriodS(r.sim_s, r.steps);
    } else {
      failures[r.failure] += 1;
    }
  }
  std::string failure_text;
  for (const auto& [what, n] : failures) failure_text += (failure_text.empty() ? "" : ", ") + what + " " + std::to_string(n);
  std::cout << "| " << scenario.name << " | " << planned << "/" << seeds << " | " << later_guide << " | " << checked
            << "/" << planned << " | "
            << reached << "/" << seeds << " | "
            << (failure_text.empty() ? "-" : failure_text) << " | "
            << (reached ? FixedNumber(time / reached, 1) + " s" : "-") << " | "
            << (reached ? FixedNumber(speed / reached, 3) + " m/s" : "-") << " | "
            << (reached ? FixedNumber(period / reached, 2) + " s" : "-") << " | "
            << (planned ? FixedNumber(steps / planned, 1) : "-") << " | " << FixedNumber(torque, 2) << " | "
            << FixedNumber(Median(rtf), 1) << "x |\n";
}

/// The success table in Markdown on stdout, and with --json every run, scenario by scenario.
void Report(const Options& o, const std::vector<Scenario>& scenarios, const std::vector<Run>& runs) {
  std::cout << "| scenario | plans | on a later guide | pass check_plan | goal reached | failures | mean time to goal | "
               "mean speed | mean step period | mean steps | max torque / limit | real-time factor (median) |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  nlohmann::json all = nlohmann::json::array();
  for (const Scenario& scenario : scenarios) {
    PrintRow(scenario, runs, o.seeds);
    for (const Run& r : runs) {
      if (r.scenario == scenario.name) all.push_back(RunJson(r));
    }
  }
  if (!o.json_path.empty()) {
    std::ofstream out(o.json_path);
    out << all.dump(1) << "\n";
  }
}

int RunBench(const Options& o) {
  Bench bench(o);
  const std::vector<Run> runs = bench.RunAll();
  Report(o, bench.scenarios(), runs);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("sim_bench", argc, argv, AddOptions, RunBench); }
