#include "rbcp/nodes/offline_pipeline.h"

#include <chrono>

#include "rbcp/core/error.h"
#include "rbcp/core/yaml_reader.h"

namespace rbcp::nodes {
namespace {

double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

nlohmann::json Vec(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

}  // namespace

PipelineStage ParseStage(const std::string& name) {
  if (name == "affordance") return PipelineStage::kAffordance;
  if (name == "root") return PipelineStage::kRoot;
  throw InputError("stage: expected 'affordance' or 'root', got '" + name + "'");
}

OfflinePipeline::OfflinePipeline(const std::string& config_dir)
    : robot_(std::make_unique<RobotModel>(RobotModel::LoadDefault(config_dir))),
      affordance_config_(AffordanceConfig::Load(YamlMap::LoadFile(config_dir + "/affordance.yaml"))),
      root_planner_(std::make_unique<RootPlanner>(
          *robot_, RootPlannerConfig::LoadFile(config_dir + "/root_planner.yaml", config_dir))) {}

PipelineResult OfflinePipeline::Run(const Scenario& scenario, PipelineStage stage, unsigned seed,
                                    double root_time_budget_s) const {
  PipelineResult result;
  result.scenario = scenario.name;
  result.seed = seed;
  result.stage = stage;

  auto start = std::chrono::steady_clock::now();
  AffordanceExtractor extractor(affordance_config_);
  result.surfaces = extractor.Extract(scenario.terrain_mesh);
  result.affordance_ms = MsSince(start);
  if (result.surfaces.empty()) {
    result.failure = "affordance: the terrain has no contact surface";
    return result;
  }
  if (stage == PipelineStage::kAffordance) return result;

  const auto start_W = root_planner_->StandingPosition(scenario.terrain_mesh, scenario.start.position);
  const auto goal_W = root_planner_->StandingPosition(scenario.terrain_mesh, scenario.goal.position);
  if (!start_W || !goal_W) {
    result.failure = std::string("root: no terrain under the ") + (!start_W ? "start" : "goal");
    return result;
  }
  result.root = root_planner_->Plan(scenario.terrain_mesh, result.surfaces, *start_W, scenario.start.yaw, *goal_W,
                                    scenario.goal.yaw, seed, root_time_budget_s);
  if (!result.root->ok()) {
    result.failure = "root: " + ToString(result.root->status) + ": " + result.root->reason;
  }
  return result;
}

nlohmann::json ToJson(const PipelineResult& result) {
  nlohmann::json j;
  j["scenario"] = result.scenario;
  j["seed"] = result.seed;
  j["affordance_ms"] = result.affordance_ms;
  j["surfaces"] = result.surfaces.size();
  if (result.root) {
    const RootPlanResult& root = *result.root;
    j["root_ok"] = root.ok();
    j["root_s"] = root.planning_time_s;
    j["root_status"] = ToString(root.status);
    j["root_duration_s"] = root.ok() ? root.path.Duration() : 0.0;
    j["root_iterations"] = root.iterations;
    nlohmann::json path = nlohmann::json::array();
    for (const auto& s : root.samples) {
      path.push_back({{"t", s.t}, {"position", Vec(s.p)}, {"velocity", Vec(s.v)}, {"yaw", s.yaw}});
    }
    j["root_path"] = path;
  } else if (result.stage != PipelineStage::kAffordance) {
    j["root_ok"] = false;
    j["root_s"] = 0.0;
    j["root_path"] = nlohmann::json::array();
  }
  j["failure"] = result.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(result.failure);
  return j;
}

}  // namespace rbcp::nodes
