// plan_scenario: the pipeline's libraries in one process on a scenario file, printing JSON.
#include <iostream>
#include <nlohmann/json.hpp>

#include "rbcp/cli/cli.h"
#include "rbcp/offline_pipeline/offline_pipeline.h"

namespace {

using namespace rbcp;

struct Options {
  cli::CommonOptions common;
  std::string scenario_path, stage = "root";
  unsigned seed = 1;
  double time_budget_s = 5.0;
  bool json = false;
};

void AddOptions(CLI::App& app, Options& o) {
  app.description(
      "Runs affordance extraction, root planning and contact planning on a scenario file in one process.\n"
      "With --stage contact --json the plan is under 'states', in the form check_plan reads; --stage sim\n"
      "then walks the plan in the simulator and adds its outcome (sim_ok, failure, sim_trace, ...).\n"
      "The JSON is described in docs/json_schema.md. Talks no LCM.\n"
      "Exit status: 0 planned, 1 a stage failed (reason in 'failure'), 2 bad input.");
  cli::AddOfflineOptions(app, o.common);
  app.add_option("--scenario", o.scenario_path, "scenario YAML")->required()->check(CLI::ExistingFile);
  app.add_option("--seed", o.seed, "random seed of the planners")->capture_default_str();
  app.add_option("--stage", o.stage, "last stage to run: affordance, root, contact or sim")->capture_default_str();
  app.add_option("--time-budget", o.time_budget_s, "root planning time budget [s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_flag("--json", o.json, "print one JSON object instead of a summary");
}

/// One line per stage that ran, then the guides without a contact plan and the failure.
void PrintSummary(const PipelineResult& result, unsigned seed) {
  std::cout << result.scenario << " (seed " << seed << "): " << result.surfaces.size() << " surfaces in "
            << result.affordance_ms << " ms";
  if (result.root) {
    std::cout << "; root " << ToString(result.root->status) << " in " << result.root->planning_time_s << " s";
    if (result.root->ok()) std::cout << ", path of " << result.root->path.Duration() << " s";
  }
  if (result.contact) {
    std::cout << "; contact " << ToString(result.contact->status) << " in " << result.contact->planning_time_s << " s";
    if (result.contact->ok) std::cout << ", " << result.contact->steps << " steps";
    if (!result.failed_guides.empty()) {
      std::cout << " along guide " << result.failed_guides.size() + 1 << " (" << result.contact_total_s
                << " s over every guide)";
    }
  }
  if (result.sim) {
    std::cout << "; sim " << (result.sim->ok() ? "goal reached" : "failed") << " after " << result.sim->sim_time_s
              << " s simulated in " << result.sim_wall_s << " s";
  }
  std::cout << "\n";
  for (const std::string& g : result.failed_guides) std::cout << "no contact plan along the guide of " << g << "\n";
  if (!result.ok()) std::cout << "failure: " << result.failure << "\n";
}

int Run(const Options& o) {
  const OfflinePipeline pipeline(o.common.config_dir);
  const PipelineResult result = pipeline.Run(LoadScenario(o.scenario_path), ParseStage(o.stage), o.seed, o.time_budget_s);
  if (o.json) {
    std::cout << ToJson(result).dump() << std::endl;
  } else {
    PrintSummary(result, o.seed);
  }
  return result.ok() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("plan_scenario", argc, argv, AddOptions, Run); }
