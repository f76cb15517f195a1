#pragma once
/// The pipeline's libraries run in one process on a scenario file, stage after stage, for
/// `plan_scenario`, the benchmarks and the tests. Same libraries and configuration as the
/// processes, no LCM.

#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/contact_planner/contact_planner.h"
#include "rbcp/controller/controller_config.h"
#include "rbcp/equilibrium/config.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/root_planner.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/sim/plan_execution.h"
#include "rbcp/sim/sim_config.h"

namespace rbcp {

enum class PipelineStage { kAffordance, kRoot, kContact, kSim };

/// "affordance", "root", "contact", "sim"; throws InputError for anything else.
PipelineStage ParseStage(const std::string& name);

struct PipelineResult {
  std::string scenario;
  unsigned seed = 0;
  PipelineStage stage = PipelineStage::kRoot;

  std::vector<AffordanceSurface> surfaces;
  double affordance_ms = 0.0;  ///< wall time of affordance extraction [ms]

  /// Set when the root stage ran: the last guide planned (RootPlannerConfig::guide_retries).
  std::optional<RootPlanResult> root;
  /// Set when the contact stage ran: the plan along `root`, or the last failure.
  std::optional<ContactPlanResult> contact;
  /// The guides along which the contact planner found no plan before `root`, in order, as
  /// "seed S: <status>: <reason>"; empty when it followed the first.
  std::vector<std::string> failed_guides;
  double contact_total_s = 0.0;  ///< wall time of contact planning over every guide [s]
  std::optional<sim::ExecutionOutcome> sim;   ///< set when the sim stage ran
  double sim_wall_s = 0.0;                    ///< wall time of the simulation [s]

  /// The first failing stage's reason, "" when every stage that ran succeeded.
  std::string failure;
  bool ok() const { return failure.empty(); }
};

/// Loads the robot and every stage's configuration once; Run() may then be called many times,
/// also from several threads.
class OfflinePipeline {
 public:
  /// Reads config_dir/{robots/anymal_b.*, affordance.yaml, root_planner.yaml, equilibrium.yaml,
  /// stance.yaml, contact_planner.yaml, limb_database.yaml, sim.yaml, controller.yaml}. Throws InputError. The limb database itself is
  /// loaded (or built and cached) by the first contact stage.
  explicit OfflinePipeline(const std::string& config_dir);

  /// Runs the stages up to `stage` on the scenario. The contact stage plans the whole root path
  /// (its samples, as ROOT_PATH carries them) with the contact planner's own time budget; when it
  /// finds no plan (no foothold, or out of budget), the next guide (root path of
  /// GuideSeed(seed, k)) is planned and followed, at most guide_retries times. The sim
  /// stage walks the contact plan in the simulator (on the same scenario) and judges the run.
  /// Planning failures are reported in the result (failure), not thrown.
  PipelineResult Run(const Scenario& scenario, PipelineStage stage, unsigned seed, double root_time_budget_s) const;

  /// Threads of each contact-planning query (the contact planner's retry.parallel_searches; its
  /// plans do not depend on it): one when several runs share the machine's cores. Not while a
  /// Run() is in progress.
  void SetContactSearchThreads(int threads);
  /// How the sim stage's controller walks (controller.yaml's mode otherwise). Not while a Run()
  /// is in progress.
  void SetWalkMode(WalkMode mode) { controller_config_.mode = mode; }

  const RobotModel& robot() const { return *robot_; }
  const RootPlanner& root_planner() const { return *root_planner_; }
  /// The limb database, loaded on first use.
  const LimbDatabase& limb_database() const;

 private:
  std::string config_dir_;
  std::unique_ptr<RobotModel> robot_;
  AffordanceConfig affordance_config_;
  std::unique_ptr<RootPlanner> root_planner_;
  EquilibriumConfig equilibrium_config_;
  ContactPlannerConfig contact_config_;
  LimbDatabaseConfig limb_database_config_;
  sim::SimConfig sim_config_;
  ControllerConfig controller_config_;
  StanceRules stance_rules_;
  mutable std::once_flag limb_database_once_;
  mutable std::unique_ptr<LimbDatabase> limb_database_;
};

/// The JSON object printed by plan_scenario: affordance_ms, surfaces, root_ok, root_s,
/// root_status, root_duration_s, root_path [{t, position, velocity, yaw}] (of the last guide); for
/// the contact stage contact_ok, contact_s (the last guide's), contact_total_s (every guide's),
/// contact_status, failed_guides, steps, reached_goal and states (the plan in the form of
/// ContactPlanToJson, read back by check_plan); for the sim stage the keys of sim::OutcomeToJson
/// (sim_ok, fell, sim_time_s, sim_trace, ...; its reached_goal replaces the contact stage's) and
/// sim_wall_s; failure (null or the reason). Keys of earlier stages stay stable as later stages
/// add theirs.
nlohmann::json ToJson(const PipelineResult& result);

}  // namespace rbcp
