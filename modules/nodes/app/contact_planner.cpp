// contact_planner: ROOT_PATH / ROBOT_STATE / TERRAIN / AFFORDANCES in, CONTACT_PLAN and STATUS out.
#include <iostream>

#include "rbcp/cli/cli.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/nodes/contact_planner_node.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/run_loop.h"

namespace {

using namespace rbcp;

struct Options {
  cli::CommonOptions common;
  std::string config_path;
  nodes::ContactPlannerNodeOptions node;
};

void AddOptions(CLI::App& app, Options& o) {
  app.description("Contact planner: footholds and whole-body states along the root path (RB-PRM limb database).");
  cli::AddCommonOptions(app, o.common);
  app.add_option("--config", o.config_path, "contact planner parameters (default: CONFIG_DIR/contact_planner.yaml)");
  app.add_option("--horizon-steps", o.node.horizon_steps,
                 "0: plan the whole path; K > 0: at most K steps from the measured robot state")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_option("--lookahead-steps", o.node.lookahead_steps,
                 "with --horizon-steps K: steps searched beyond the K published, so they lead on (the default reaches the goal)")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_flag_callback(
      "--realtime", [&o] { o.node.wait_for_search_ahead = false; },
      "with --horizon-steps K: the robot walks on the wall clock (anymal_sim --realtime-factor 1): a step boundary "
      "does not wait for a search made ahead that has not ended; the earlier search goes on");
  app.add_flag("--partial-map", o.node.partial_map,
               "with --horizon-steps K: the terrain is a map that grows as the robot walks (terrain_mapper): a wait is "
               "answered on the map of its time, never on an older one");
}

int Run(const Options& o) {
  const std::string& dir = o.common.config_dir;
  const RobotModel robot = RobotModel::LoadDefault(dir);
  const auto equilibrium = EquilibriumConfig::LoadFile(dir + "/equilibrium.yaml");
  const auto config = ContactPlannerConfig::LoadFile(o.config_path.empty() ? dir + "/contact_planner.yaml" : o.config_path);
  const LimbDatabase database = nodes::LoadLimbDatabase(robot, dir, !o.common.quiet);
  const StanceConfig stance = StanceConfig::LoadFile(dir + "/stance.yaml");
  auto lcm = transport::OpenLcm(o.common.lcm_url);
  nodes::ContactPlannerNode node(*lcm, robot, database, equilibrium, config, stance, o.node);
  node.set_verbose(!o.common.quiet);
  std::cerr << "[contact_planner] listening: ROOT_PATH, ROBOT_STATE, TERRAIN, AFFORDANCES -> CONTACT_PLAN, STATUS ("
            << (o.node.horizon_steps > 0 ? "horizon of " + std::to_string(o.node.horizon_steps) + " steps"
                                         : std::string("whole path"))
            << ")\n";
  // STATUS at least every 0.4 s, also while working; BUSY far beyond the budget of its queries
  // (a replan makes at most three) is stuck (the heartbeat falls silent and the supervisor
  // restarts it).
  node.status().StartBackgroundHeartbeat(0.4, 3.0 * config.time_budget_s + 30.0);
  return transport::RunLoop(*lcm, [&] { node.Step(); }, [&] { node.Heartbeat(); }, {1.0, 20, o.common.max_runtime_s});
}

}  // namespace

int main(int argc, char** argv) {
  return rbcp::cli::Main(rbcp::nodes::ContactPlannerNode::kProcessName, argc, argv, AddOptions, Run);
}
