// affordance_extractor: TERRAIN in, AFFORDANCES and STATUS out; or one scenario file with --once.
#include <iostream>
#include <nlohmann/json.hpp>

#include "rbcp/cli/cli.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/nodes/affordance_node.h"
#include "rbcp/nodes/affordance_offline.h"
#include "rbcp/transport/run_loop.h"

namespace {

using namespace rbcp;

struct Options {
  cli::CommonOptions common;
  std::string scenario_path, config_path;
  bool once = false, json = false;
};

void AddOptions(CLI::App& app, Options& o) {
  app.description("Affordance extraction: terrain mesh (TERRAIN) -> convex contact surfaces (AFFORDANCES).");
  cli::AddCommonOptions(app, o.common);
  app.add_option("--scenario", o.scenario_path, "scenario YAML to extract from instead of listening (needs --once)")
      ->check(CLI::ExistingFile);
  app.add_flag("--once", o.once, "extract from --scenario, print the result and exit");
  app.add_flag("--json", o.json, "with --once: print one JSON object (surfaces, extract_ms)");
  app.add_option("--config", o.config_path, "affordance parameters (default: CONFIG_DIR/affordance.yaml)");
}

/// The process: TERRAIN in, AFFORDANCES out, until stopped.
int Serve(const Options& o, const AffordanceConfig& config) {
  auto lcm = transport::OpenLcm(o.common.lcm_url);
  nodes::AffordanceNode node(*lcm, config);
  node.status().set_verbose(!o.common.quiet);
  std::cerr << "[affordance_extractor] listening: TERRAIN -> AFFORDANCES, STATUS\n";
  // STATUS at least every 0.4 s, also while working; two minutes on one terrain is stuck (the
  // heartbeat falls silent and the supervisor restarts it).
  node.status().StartBackgroundHeartbeat(0.4, 120.0);
  return transport::RunLoop(*lcm, [&] { node.Step(); }, [&] { node.Heartbeat(); }, {1.0, 20, o.common.max_runtime_s});
}

int Run(const Options& o) {
  const auto config = AffordanceConfig::Load(
      YamlMap::LoadFile(o.config_path.empty() ? o.common.config_dir + "/affordance.yaml" : o.config_path));
  if (o.once != !o.scenario_path.empty()) throw InputError("--once and --scenario go together (see --help)");
  if (!o.once) return Serve(o, config);
  const auto report = nodes::ExtractScenario(o.scenario_path, config);
  std::cout << (o.json ? nodes::ToJson(report).dump() : nodes::Summary(report)) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return rbcp::cli::Main(rbcp::nodes::AffordanceNode::kProcessName, argc, argv, AddOptions, Run);
}
