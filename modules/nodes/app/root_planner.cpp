// root_planner: PLAN_REQUEST / ROBOT_STATE / TERRAIN / AFFORDANCES in, ROOT_PATH and STATUS out.
#include <iostream>

#include "rbcp/cli/cli.h"
#include "rbcp/nodes/root_planner_node.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/run_loop.h"

namespace {

using namespace rbcp;

struct Options {
  cli::CommonOptions common;
  std::string config_path;
  nodes::RootPlannerNodeOptions node;
};

void AddOptions(CLI::App& app, Options& o) {
  app.description("Root (trunk) path planner: kinodynamic bidirectional RRT under the reachability condition.");
  cli::AddCommonOptions(app, o.common);
  app.add_option("--config", o.config_path, "root planner parameters (default: CONFIG_DIR/root_planner.yaml)");
  app.add_option("--time-budget", o.node.default_time_budget_s, "planning budget when a request gives none [s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_flag("--partial-map", o.node.partial_map,
               "the terrain is a map that grows as the robot walks (terrain_mapper): plan towards a goal the map does "
               "not show yet, and again on every new map while the robot waits at a step boundary");
}

int Run(const Options& o) {
  const RobotModel robot = RobotModel::LoadDefault(o.common.config_dir);
  auto config = RootPlannerConfig::LoadFile(
      o.config_path.empty() ? o.common.config_dir + "/root_planner.yaml" : o.config_path, o.common.config_dir);
  auto lcm = transport::OpenLcm(o.common.lcm_url);
  nodes::RootPlannerNode node(*lcm, robot, std::move(config), o.node);
  node.status().set_verbose(!o.common.quiet);
  std::cerr << "[root_planner] listening: PLAN_REQUEST, ROBOT_STATE, TERRAIN, AFFORDANCES -> ROOT_PATH, STATUS\n";
  // STATUS at least every 0.4 s, also while working; BUSY far beyond the largest budget a
  // request may ask for is stuck (the heartbeat falls silent and the supervisor restarts it).
  node.status().StartBackgroundHeartbeat(0.4, 2.0 * o.node.max_time_budget_s + 30.0);
  return transport::RunLoop(*lcm, [&] { node.Step(); }, [&] { node.Heartbeat(); }, {1.0, 20, o.common.max_runtime_s});
}

}  // namespace

int main(int argc, char** argv) {
  return rbcp::cli::Main(rbcp::nodes::RootPlannerNode::kProcessName, argc, argv, AddOptions, Run);
}
