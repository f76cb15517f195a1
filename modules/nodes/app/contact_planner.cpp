// contact_planner: ROOT_PATH / ROBOT_STATE / TERRAIN / AFFORDANCES in, CONTACT_PLAN and STATUS out.
#include <iostream>

#include "rbcp/limb_database/limb_database.h"
#include "rbcp/nodes/contact_planner_node.h"
#include "rbcp/cli/cli.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/run_loop.h"

int main(int argc, char** argv) {
  using namespace rbcp;
  CLI::App app{"Contact planner: footholds and whole-body states along the root path (RB-PRM limb database)."};
  cli::CommonOptions common;
  cli::AddCommonOptions(app, common);
  std::string config;
  nodes::ContactPlannerNodeOptions options;
  app.add_option("--config", config, "contact planner parameters (default: CONFIG_DIR/contact_planner.yaml)");
  app.add_option("--horizon-steps", options.horizon_steps,
                 "0: plan the whole path; K > 0: at most K steps from the measured robot state")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_option("--lookahead-steps", options.lookahead_steps,
                 "with --horizon-steps K: steps searched beyond the K published, so they lead on (the default reaches the goal)")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  return cli::GuardedMain(nodes::ContactPlannerNode::kProcessName, app, argc, argv, [&] {
    const RobotModel robot = RobotModel::LoadDefault(common.config_dir);
    const auto eq = EquilibriumConfig::LoadFile(common.config_dir + "/equilibrium.yaml");
    const auto cfg = ContactPlannerConfig::LoadFile(config.empty() ? common.config_dir + "/contact_planner.yaml" : config);
    const LimbDatabase database = nodes::LoadLimbDatabase(robot, common.config_dir, !common.quiet);
    auto lcm = transport::OpenLcm(common.lcm_url);
    const StanceConfig stance = StanceConfig::LoadFile(common.config_dir + "/stance.yaml");
    nodes::ContactPlannerNode node(*lcm, robot, database, eq, cfg, stance, options);
    node.set_verbose(!common.quiet);
    std::cerr << "[contact_planner] listening: ROOT_PATH, ROBOT_STATE, TERRAIN, AFFORDANCES -> CONTACT_PLAN, STATUS ("
              << (options.horizon_steps > 0 ? "horizon of " + std::to_string(options.horizon_steps) + " steps"
                                            : std::string("whole path")) << ")\n";
    // STATUS at least every 0.4 s, also while working; BUSY far beyond the budget of its queries
    // (a replan makes at most three) is stuck (the heartbeat falls silent and the supervisor
    // restarts it).
    node.status().StartBackgroundHeartbeat(0.4, 3.0 * cfg.time_budget_s + 30.0);
    return transport::RunLoop(*lcm, [&] { node.Step(); }, [&] { node.Heartbeat(); }, {1.0, 20, common.max_runtime_s});
  });
}
