// root_planner: PLAN_REQUEST / ROBOT_STATE / TERRAIN / AFFORDANCES in, ROOT_PATH and STATUS out.
#include <iostream>

#include "rbcp/cli/cli.h"
#include "rbcp/nodes/root_planner_node.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/run_loop.h"

int main(int argc, char** argv) {
  using namespace rbcp;
  CLI::App app{"Root (trunk) path planner: kinodynamic bidirectional RRT under the reachability condition."};
  cli::CommonOptions common;
  cli::AddCommonOptions(app, common);
  std::string config;
  nodes::RootPlannerNodeOptions options;
  app.add_option("--config", config, "root planner parameters (default: CONFIG_DIR/root_planner.yaml)");
  app.add_option("--time-budget", options.default_time_budget_s, "planning budget when a request gives none [s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  return cli::GuardedMain(nodes::RootPlannerNode::kProcessName, app, argc, argv, [&] {
    const RobotModel robot = RobotModel::LoadDefault(common.config_dir);
    auto cfg = RootPlannerConfig::LoadFile(config.empty() ? common.config_dir + "/root_planner.yaml" : config,
                                           common.config_dir);
    auto lcm = transport::OpenLcm(common.lcm_url);
    nodes::RootPlannerNode node(*lcm, robot, std::move(cfg), options);
    node.status().set_verbose(!common.quiet);
    std::cerr << "[root_planner] listening: PLAN_REQUEST, ROBOT_STATE, TERRAIN, AFFORDANCES -> ROOT_PATH, STATUS\n";
    // STATUS at least every 0.4 s, also while working; BUSY far beyond the largest budget a
    // request may ask for is stuck (the heartbeat falls silent and the supervisor restarts it).
    node.status().StartBackgroundHeartbeat(0.4, 2.0 * options.max_time_budget_s + 30.0);
    return transport::RunLoop(*lcm, [&] { node.Step(); }, [&] { node.Heartbeat(); }, {1.0, 20, common.max_runtime_s});
  });
}
