// anymal_sim: the simulator. As a process it is the world (TERRAIN, ROBOT_STATE, STATUS out,
// CONTACT_PLAN in); with --plan it executes one plan offline and prints the outcome.
#include <chrono>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "rbcp/controller/controller_config.h"
#include "rbcp/core/error.h"
#include "rbcp/cli/cli.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/sim/plan_execution.h"
#include "rbcp/sim/sim_node.h"
#include "rbcp/sim/world_events.h"
#include "rbcp/transport/run_loop.h"
namespace {

using namespace rbcp;
using Clock = std::chrono::steady_clock;

/// [m] how far from the scenario's goal a plan may end and still reach it (the contact planner
/// ends its plans at the root path's end, the goal, give or take the body's shift).
constexpr double kGoalReach_m = 0.3;

/// The command line.
struct Options {
  cli::CommonOptions common;
  std::string scenario_path, plan_path, sim_config_path, controller_config_path, log_csv_path, events_path, walk;
  bool json = false, exit_when_decided = false;
  sim::SimNodeOptions node_options;
  double realtime_factor = 1.0;
  long long sensor_seed = -1;  ///< overrides sensing.noise_seed when >= 0
  std::string terrain = "ground_truth";
};

void AddOptions(CLI::App& app, Options& o) {
  cli::AddCommonOptions(app, o.common);
  app.add_option("--scenario", o.scenario_path, "scenario YAML: the world (terrain, and the start the robot stands on)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--plan", o.plan_path, "execute this contact plan (JSON as plan_scenario --stage contact prints it, "
                                        "'-' for standard input) and exit");
  app.add_flag("--json", o.json, "with --plan: print the outcome as one JSON object (with the 20 Hz trace)");
  app.add_option("--log-csv", o.log_csv_path,
                 "with --plan: write every control tick to this CSV file (controller phase, step, support margin, "
                 "base pose and reference, joint positions and torques, foot contacts and normal forces)");
  app.add_option("--realtime-factor", o.realtime_factor,
                 "process: simulated seconds per wall second (0: as fast as possible)")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_flag("--exit-when-decided", o.exit_when_decided,
               "process: exit once a plan's outcome is decided (status 0 goal reached, 1 failed)");
  app.add_flag("--replan", o.node_options.replan,
               "process: the robot stops at every step boundary until a CONTACT_PLAN starting from that stance "
               "comes (receding-horizon replanning; the world stands still meanwhile unless --realtime-factor > 0)");
  app.add_option("--await-timeout", o.node_options.await_timeout_s,
                 "process, --replan: wall seconds to wait for a plan before going on with the current one")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--events", o.events_path,
                 "process: scripted changes of the world at simulated times (YAML: add_box, remove_box, push, goal)")
      ->check(CLI::ExistingFile);
  app.add_option("--sim-config", o.sim_config_path, "simulator parameters (default: CONFIG_DIR/sim.yaml)");
  app.add_option("--sensor-seed", o.sensor_seed,
                 "seed of the depth sensors' range noise (overrides sensing.noise_seed; the same seed gives the "
                 "same POINT_CLOUD messages)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--terrain", o.terrain,
                 "what the planners plan on: ground_truth (the true terrain on TERRAIN; no sensor runs) or perceived "
                 "(the depth sensors' POINT_CLOUD for terrain_mapper, the true terrain on TERRAIN_TRUTH); with --plan, "
                 "perceived runs the sensors as the process does, to measure their cost")
      ->capture_default_str()->check(CLI::IsMember({"ground_truth", "perceived"}));
  app.add_option("--controller-config", o.controller_config_path,
                 "controller parameters (default: CONFIG_DIR/controller.yaml)");
  app.add_option("--walk", o.walk, "how the controller walks: static or dynamic (default: the controller file's mode)")
      ->check(CLI::IsMember({"static", "dynamic"}));

  app.description(
      "ANYmal B in a Bullet simulation, walked by the onboard plan controller.\n"
      "Process: publishes TERRAIN (or, with --terrain perceived, POINT_CLOUD from the depth sensors of\n"
      "sim.yaml's sensing map and the true terrain on TERRAIN_TRUTH), ROBOT_STATE (at the control rate of\n"
      "simulated time) and STATUS, and walks every CONTACT_PLAN it receives. Offline (--plan): executes one\n"
      "plan on the scenario and prints the outcome (with --terrain perceived the sensors capture as in the\n"
      "process, nothing is published); exit status 0 goal reached, 1 the run failed, 2 bad input.");
}

/// The controller file (CONFIG_DIR/controller.yaml or --controller-config), its mode set by --walk.
ControllerConfig LoadControllerConfig(const Options& o) {
  ControllerConfig config = ControllerConfig::LoadFile(
      o.controller_config_path.empty() ? o.common.config_dir + "/controller.yaml" : o.controller_config_path);
  if (!o.walk.empty()) config.mode = *ValueOf(o.walk, WalkModeNames());  // --walk checked it
  return config;
}

/// The simulator file (CONFIG_DIR/sim.yaml or --sim-config), its noise seed set by --sensor-seed.
sim::SimConfig LoadSimConfig(const Options& o) {
  sim::SimConfig config =
      sim::SimConfig::LoadFile(o.sim_config_path.empty() ? o.common.config_dir + "/sim.yaml" : o.sim_config_path);
  if (o.sensor_seed >= 0) config.sensing.noise_seed = static_cast<std::uint64_t>(o.sensor_seed);
  return config;
}

/// The simulated world: its configuration, the robot, the scenario, the stance rules, and the
/// execution of plans on them (which keeps references to them: a World is not copied).
struct World {
  explicit World(const Options& o)
      : sim_config(LoadSimConfig(o)),
        controller_config(LoadControllerConfig(o)),
        robot(RobotModel::LoadDefault(o.common.config_dir)),
        scenario(LoadScenario(o.scenario_path)),
        stance(StanceRules::LoadFromDir(o.common.config_dir)),
        execution(robot, scenario, sim_config, controller_config, stance) {}
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  const sim::SimConfig sim_config;
  const ControllerConfig controller_config;
  const RobotModel robot;
  const Scenario scenario;
  const StanceRules stance;
  sim::PlanExecution execution;
};

/// Runs the started execution to its end, `after_tick` called after every control tick and, with
/// a `csv_path`, every tick written to that CSV file.
template <typename AfterTick>
void RunExecution(sim::PlanExecution& execution, const std::string& csv_path, AfterTick&& after_tick) {
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv) throw InputError("cannot write " + csv_path);
    sim::WriteTickCsvHeader(csv);
  }
  bool more = true;
  while (more) {
    if (!csv_path.empty()) sim::WriteTickCsvRow(csv, execution);
    more = execution.Tick();
    after_tick();
  }
  if (!csv_path.empty()) {
    sim::WriteTickCsvRow(csv, execution);
    if (!csv) throw InputError("cannot write " + csv_path);
  }
}

/// --plan: executes the plan offline and prints the outcome; returns the exit status.
int ExecutePlan(const Options& o, World& world) {
  const ContactPlan plan = LoadContactPlanFile(o.plan_path);
  world.execution.Start(plan);
  // With --terrain perceived the depth sensors capture as the process's would (the same cost), for no one.
  sim::SensingConfig sensing = world.sim_config.sensing;
  if (o.terrain != "perceived") sensing.enabled = false;
  sim::SensorRig sensors(sensing, world.sim_config.control_rate_hz);
  long clouds = 0;
  const auto start = Clock::now();
  if (o.log_csv_path.empty() && sensors.Empty()) {
    world.execution.Run();
  } else {
    RunExecution(world.execution, o.log_csv_path, [&] {
      if (!sensors.Empty()) {
        clouds += static_cast<long>(sensors.CaptureIfDue(world.execution.World(), world.execution.State()).size());
      }
    });
  }
  // The plan's verdict is about the plan; the run's is about the scenario: a plan that ends
  // away from the scenario's goal does not reach it, however well it was walked.
  sim::ExecutionOutcome outcome = world.execution.Outcome();
  sim::JudgeAgainstGoal(outcome, plan, world.scenario.goal, kGoalReach_m);
  const double wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  if (o.json) {
    nlohmann::json j = sim::OutcomeToJson(outcome);
    AddSchemaKeys(j);
    j["scenario"] = world.scenario.name;
    j["sim_failure"] = j["failure"];  // as plan_scenario names it
    j["sim_wall_s"] = wall_s;
    std::cout << j.dump() << std::endl;
  } else {
    std::cout << "anymal_sim: " << sim::OutcomeSummary(outcome) << " (" << wall_s << " s wall, "
              << outcome.sim_time_s / std::max(wall_s, 1e-9) << "x real time, " << clouds << " point clouds)"
              << std::endl;
  }
  return outcome.ok() ? 0 : 1;
}

/// The process: the world on LCM, ticking until stopped (or, with --exit-when-decided, until a
/// plan's outcome is decided); returns the exit status.
int ServeWorld(const Options& o, World& world) {
  sim::SimNodeOptions node_options = o.node_options;
  if (!o.events_path.empty()) node_options.events = sim::LoadWorldEvents(o.events_path);
  auto lcm = transport::OpenLcm(o.common.lcm_url);
  node_options.pause_while_awaiting = o.realtime_factor <= 0.0;
  node_options.terrain = *ValueOf(o.terrain, sim::TerrainSourceNames());  // --terrain checked it
  sim::SimNode node(*lcm, world.execution, world.scenario, world.sim_config, node_options);
  node.status().set_verbose(!o.common.quiet);
  node.status().StartBackgroundHeartbeat(0.4);
  transport::InstallStopHandlers();
  std::cerr << "[anymal_sim] " << world.scenario.name << ": TERRAIN, ROBOT_STATE, STATUS out; CONTACT_PLAN in; "
            << (o.realtime_factor > 0 ? std::to_string(o.realtime_factor) + "x real time" : std::string("as fast as possible"))
            << (node_options.replan ? "; replanning at every step boundary" : "") << "\n";
  const auto start = Clock::now();
  auto next_heartbeat = start;
  while (!transport::StopRequested()) {
    while (lcm->handleTimeout(0) > 0) {
    }
    node.Tick();
    const auto now = Clock::now();
    if (now >= next_heartbeat) {
      node.Heartbeat();
      next_heartbeat = now + std::chrono::milliseconds(250);
    }
    if (o.exit_when_decided && node.Decided()) {
      node.Heartbeat();
      return world.execution.Outcome().ok() ? 0 : 1;
    }
    const double wall_s = std::chrono::duration<double>(now - start).count();
    if (o.common.max_runtime_s > 0 && wall_s > o.common.max_runtime_s) break;
    if (node.Paused()) {
      lcm->handleTimeout(1);  // the world stands still: wait for the plan without spinning
    } else if (o.realtime_factor > 0) {
      std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(
                                                std::chrono::duration<double>(node.SimTime() / o.realtime_factor)));
    }
  }
  return 0;
}

int Run(const Options& o) {
  World world(o);
  return o.plan_path.empty() ? ServeWorld(o, world) : ExecutePlan(o, world);
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main(sim::SimNode::kProcessName, argc, argv, AddOptions, Run); }
