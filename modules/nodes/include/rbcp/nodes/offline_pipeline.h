#pragma once
/// The pipeline's libraries run in one process on a scenario file, stage after stage, for
/// `plan_scenario`, the benchmarks and the tests. Same libraries and configuration as the
/// processes, no LCM.

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/root_planner.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp::nodes {

enum class PipelineStage { kAffordance, kRoot };

/// "affordance", "root"; throws InputError for anything else.
PipelineStage ParseStage(const std::string& name);

struct PipelineResult {
  std::string scenario;
  unsigned seed = 0;
  PipelineStage stage = PipelineStage::kRoot;

  std::vector<AffordanceSurface> surfaces;
  double affordance_ms = 0.0;  ///< wall time of affordance extraction [ms]

  std::optional<RootPlanResult> root;  ///< set when the root stage ran

  /// The first failing stage's reason, "" when every stage that ran succeeded.
  std::string failure;
  bool ok() const { return failure.empty(); }
};

/// Loads the robot and every stage's configuration once; Run() may then be called many times.
class OfflinePipeline {
 public:
  /// Reads config_dir/{robots/anymal_b.*, affordance.yaml, root_planner.yaml}. Throws InputError.
  explicit OfflinePipeline(const std::string& config_dir);

  /// Runs the stages up to `stage` on the scenario. Planning failures are reported in the
  /// result (failure), not thrown.
  PipelineResult Run(const Scenario& scenario, PipelineStage stage, unsigned seed, double root_time_budget_s) const;

  const RobotModel& robot() const { return *robot_; }
  const RootPlanner& root_planner() const { return *root_planner_; }

 private:
  std::unique_ptr<RobotModel> robot_;
  AffordanceConfig affordance_config_;
  std::unique_ptr<RootPlanner> root_planner_;
};

/// The JSON object printed by plan_scenario: affordance_ms, surfaces, root_ok, root_s,
/// root_status, root_duration_s, root_path [{t, position, velocity, yaw}], failure (null or the
/// reason). Keys of earlier stages stay stable as later stages add theirs.
nlohmann::json ToJson(const PipelineResult& result);

}  // namespace rbcp::nodes
