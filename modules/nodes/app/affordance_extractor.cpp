// affordance_extractor: TERRAIN in, AFFORDANCES and STATUS out; or one scenario file with --once.
#include <iostream>

#include "rbcp/core/yaml_reader.h"
#include "rbcp/nodes/affordance_node.h"
#include "rbcp/nodes/affordance_offline.h"
#include "rbcp/cli/cli.h"
#include "rbcp/transport/run_loop.h"

int main(int argc, char** argv) {
  using namespace rbcp;
  CLI::App app{"Affordance extraction: terrain mesh (TERRAIN) -> convex contact surfaces (AFFORDANCES)."};
  cli::CommonOptions common;
  cli::AddCommonOptions(app, common);
  std::string scenario, config;
  bool once = false, json = false;
  app.add_option("--scenario", scenario, "scenario YAML to extract from instead of listening (needs --once)")
      ->check(CLI::ExistingFile);
  app.add_flag("--once", once, "extract from --scenario, print the result and exit");
  app.add_flag("--json", json, "with --once: print one JSON object (surfaces, extract_ms)");
  app.add_option("--config", config, "affordance parameters (default: CONFIG_DIR/affordance.yaml)");
  return cli::GuardedMain(nodes::AffordanceNode::kProcessName, app, argc, argv, [&] {
    const auto cfg = AffordanceConfig::Load(YamlMap::LoadFile(config.empty() ? common.config_dir + "/affordance.yaml" : config));
    if (once != !scenario.empty()) throw InputError("--once and --scenario go together (see --help)");
    if (once) {
      const auto report = nodes::ExtractScenario(scenario, cfg);
      std::cout << (json ? nodes::ToJson(report).dump() : nodes::Summary(report)) << std::endl;
      return 0;
    }
    auto lcm = transport::OpenLcm(common.lcm_url);
    nodes::AffordanceNode node(*lcm, cfg);
    node.status().set_verbose(!common.quiet);
    std::cerr << "[affordance_extractor] listening: TERRAIN -> AFFORDANCES, STATUS\n";
    // STATUS at least every 0.4 s, also while working; two minutes on one terrain is stuck (the
    // heartbeat falls silent and the supervisor restarts it).
    node.status().StartBackgroundHeartbeat(0.4, 120.0);
    return transport::RunLoop(*lcm, [&] { node.Step(); }, [&] { node.Heartbeat(); }, {1.0, 20, common.max_runtime_s});
  });
}
