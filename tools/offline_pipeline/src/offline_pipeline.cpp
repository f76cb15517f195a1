#include "rbcp/offline_pipeline/offline_pipeline.h"

#include <chrono>
#include <nlohmann/json.hpp>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/plan_checker/plan_json.h"

namespace rbcp {
namespace {

double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

nlohmann::json Vec(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

}  // namespace

PipelineStage ParseStage(const std::string& name) {
  if (name == "affordance") return PipelineStage::kAffordance;
  if (name == "root") return PipelineStage::kRoot;
  if (name == "contact") return PipelineStage::kContact;
  if (name == "sim") return PipelineStage::kSim;
  throw InputError("stage: expected 'affordance', 'root', 'contact' or 'sim', got '" + name + "'");
}

OfflinePipeline::OfflinePipeline(const std::string& config_dir)
    : config_dir_(config_dir),
      robot_(std::make_unique<RobotModel>(RobotModel::LoadDefault(config_dir))),
      affordance_config_(AffordanceConfig::Load(YamlMap::LoadFile(config_dir + "/affordance.yaml"))),
      root_planner_(std::make_unique<RootPlanner>(
          *robot_, RootPlannerConfig::LoadFile(config_dir + "/root_planner.yaml", config_dir))),
      equilibrium_config_(EquilibriumConfig::LoadFile(config_dir + "/equilibrium.yaml")),
      contact_config_(ContactPlannerConfig::LoadFile(config_dir + "/contact_planner.yaml")),
      limb_database_config_(LimbDatabaseConfig::LoadFile(config_dir + "/limb_database.yaml")),
      sim_config_(sim::SimConfig::LoadFile(config_dir + "/sim.yaml")),
      controller_config_(ControllerConfig::LoadFile(config_dir + "/controller.yaml")),
      stance_rules_(StanceRules::LoadFromDir(config_dir)) {}

void OfflinePipeline::SetContactSearchThreads(int threads) {
  ContactPlannerConfig config = contact_config_;
  config.retry.parallel_searches = threads;
  config.Validate("contact search threads");
  contact_config_ = config;
}

const LimbDatabase& OfflinePipeline::limb_database() const {
  std::call_once(limb_database_once_, [this] {
    limb_database_ = std::make_unique<LimbDatabase>(LimbDatabase::LoadOrBuild(
        *robot_, LimbDatabase::DefaultRobotFiles(config_dir_), limb_database_config_));
  });
  return *limb_database_;
}

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
  // Each guide (root path) in turn until the contact planner follows one: a guide along which
  // it finds no foothold, or runs out of budget, is replaced by the next (guide_retries).
  std::optional<ContactPlanner> contact_planner;
  for (int guide = 0;; ++guide) {
    const unsigned guide_seed = GuideSeed(seed, guide);
    result.root = root_planner_->Plan(scenario.terrain_mesh, result.surfaces, *start_W, scenario.start.yaw, *goal_W,
                                      scenario.goal.yaw, guide_seed, root_time_budget_s);
    if (!result.root->ok()) {
      result.failure = "root: " + ToString(result.root->status) + ": " + result.root->reason;
      return result;
    }
    if (stage == PipelineStage::kRoot) return result;
    if (!contact_planner) {
      contact_planner.emplace(*robot_, limb_database(), equilibrium_config_, contact_config_, stance_rules_.config);
      contact_planner->SetTerrain(scenario.terrain_mesh, result.surfaces);
    }
    result.contact = contact_planner->Plan(result.root->samples);
    result.contact_total_s += result.contact->planning_time_s;
    if (result.contact->ok) break;
    const std::string why = ToString(result.contact->status) + ": " + result.contact->reason;
    if (!FailedAlongPath(result.contact->status) || guide >= root_planner_->config().guide_retries) {
      result.failure = "contact: " + why;
      return result;
    }
    result.failed_guides.push_back("seed " + std::to_string(guide_seed) + ": " + why);
  }
  if (stage == PipelineStage::kContact) return result;

  start = std::chrono::steady_clock::now();
  sim::PlanExecution execution(*robot_, scenario, sim_config_, controller_config_, stance_rules_);
  execution.Start(result.contact->plan);
  result.sim = execution.Run();
  result.sim_wall_s = MsSince(start) / 1000.0;
  if (!result.sim->ok()) {
    const auto& f = result.sim->failure;
    result.failure = "sim: " + (f ? f->what + " at " + FixedNumber(f->t, 2) + " s, step " + std::to_string(f->step) +
                                        (f->leg.empty() ? "" : " (" + f->leg + ")") + " during " + f->phase + ": " +
                                        f->detail +
                                        (f->should_have_caught.empty() ? "" : " [should have been caught: " +
                                                                                   f->should_have_caught + "]")
                                  : std::string("the goal was not reached"));
  }
  return result;
}

nlohmann::json ToJson(const PipelineResult& result) {
  nlohmann::json j;
  AddSchemaKeys(j);
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
  if (result.contact) {
    const ContactPlanResult& contact = *result.contact;
    j["contact_ok"] = contact.ok;
    j["contact_s"] = contact.planning_time_s;
    j["contact_total_s"] = result.contact_total_s;
    j["contact_status"] = ToString(contact.status);
    j["failed_guides"] = result.failed_guides;
    j["steps"] = contact.ok ? contact.steps : 0;
    j["reached_goal"] = contact.reached_goal;
    j["states"] = contact.ok ? ContactPlanToJson(contact.plan) : nlohmann::json::array();
  } else if (result.stage == PipelineStage::kContact || result.stage == PipelineStage::kSim) {
    j["contact_ok"] = false;
    j["contact_s"] = 0.0;
    j["contact_total_s"] = 0.0;
    j["failed_guides"] = nlohmann::json::array();
    j["steps"] = 0;
    j["states"] = nlohmann::json::array();
  }
  if (result.sim) {
    j.update(sim::OutcomeToJson(*result.sim));
    j["sim_failure"] = j["failure"];  // the simulator's failure object; "failure" below is the run's text
    j["sim_wall_s"] = result.sim_wall_s;
  } else if (result.stage == PipelineStage::kSim) {
    j["sim_ok"] = false;
    j["reached_goal"] = false;
    j["fell"] = false;
    j["sim_time_s"] = 0.0;
    j["sim_wall_s"] = 0.0;
    j["sim_failure"] = nullptr;
    j["sim_trace"] = nlohmann::json::array();
  }
  j["failure"] = result.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(result.failure);
  return j;
}

}  // namespace rbcp
