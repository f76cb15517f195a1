#pragma once
// Shared fixtures of the contact planner tests: the robot, a small limb database cached under the
// test temporary folder, scenario worlds with their contact surfaces and root paths, and the
// check of a plan by the plan checker and the stance rules.

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/contact_planner/contact_planner.h"
#include "rbcp/core/pose.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/plan_checker/plan_checker.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/root_planner.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/stance/stance_checker.h"

namespace rbcp::test {

inline const std::string kConfigDir = std::string(RBCP_SOURCE_DIR) + "/config";

inline const RobotModel& Robot() {
  static const RobotModel robot = RobotModel::LoadDefault(kConfigDir);
  return robot;
}

/// 10,000 samples per leg (the default is 50,000), cached in the test temporary folder.
inline const LimbDatabase& SmallDatabase() {
  static const LimbDatabase db = [] {
    LimbDatabaseConfig config = LimbDatabaseConfig::LoadFile(kConfigDir + "/limb_database.yaml");
    config.samples_per_leg = 10000;
    config.cache_dir = ::testing::TempDir() + "/rbcp_contact_planner_test_limb_db";
    return LimbDatabase::LoadOrBuild(Robot(), LimbDatabase::DefaultRobotFiles(kConfigDir), config);
  }();
  return db;
}

inline const EquilibriumConfig& Equilibrium() {
  static const EquilibriumConfig config = EquilibriumConfig::LoadFile(kConfigDir + "/equilibrium.yaml");
  return config;
}

inline const ContactPlannerConfig& PlannerConfig() {
  static const ContactPlannerConfig config = ContactPlannerConfig::LoadFile(kConfigDir + "/contact_planner.yaml");
  return config;
}

/// A terrain with its contact surfaces.
struct World {
  std::string name;
  TriangleMesh terrain;
  std::vector<AffordanceSurface> surfaces;
  Scenario scenario;  ///< empty for worlds built in code
};

inline std::vector<AffordanceSurface> ExtractSurfaces(const TriangleMesh& terrain) {
  AffordanceExtractor extractor(AffordanceConfig::Load(YamlMap::LoadFile(kConfigDir + "/affordance.yaml")));
  return extractor.Extract(terrain);
}

inline const World& ScenarioWorld(const std::string& name) {
  static std::map<std::string, std::unique_ptr<World>> worlds;
  auto it = worlds.find(name);
  if (it == worlds.end()) {
    auto w = std::make_unique<World>();
    w->name = name;
    w->scenario = LoadScenario(kConfigDir + "/scenarios/" + name + ".yaml");
    w->terrain = w->scenario.terrain_mesh;
    w->surfaces = ExtractSurfaces(w->terrain);
    it = worlds.emplace(name, std::move(w)).first;
  }
  return *it->second;
}

inline const RootPlanner& RootPlannerInstance() {
  static const RootPlanner planner(Robot(), RootPlannerConfig::LoadFile(kConfigDir + "/root_planner.yaml", kConfigDir));
  return planner;
}

/// The root path of a scenario for a seed (planned once per scenario and seed).
inline const RootPlanResult& ScenarioRootPath(const std::string& name, unsigned seed) {
  static std::map<std::pair<std::string, unsigned>, RootPlanResult> paths;
  const auto key = std::make_pair(name, seed);
  auto it = paths.find(key);
  if (it == paths.end()) {
    const World& w = ScenarioWorld(name);
    const RootPlanner& planner = RootPlannerInstance();
    const auto start = planner.StandingPosition(w.terrain, w.scenario.start.position);
    const auto goal = planner.StandingPosition(w.terrain, w.scenario.goal.position);
    RootPlanResult r;
    if (start && goal) {
      r = planner.Plan(w.terrain, w.surfaces, *start, w.scenario.start.yaw, *goal, w.scenario.goal.yaw, seed, 20.0);
    } else {
      r.reason = "no terrain under the start or goal";
    }
    it = paths.emplace(key, std::move(r)).first;
  }
  return it->second;
}

inline const StanceRules& Rules() {
  static const StanceRules rules = StanceRules::LoadFromDir(kConfigDir);
  return rules;
}

/// Verification of a plan against its world and root path: its ends on the path, every state and
/// step by the plan checker (with the planner's own torque ceiling), and every step as the
/// controller walks it (StanceChecker::CheckStep).
inline void ExpectValidPlan(const ContactPlan& plan, const World& world, const std::vector<RootPathSample>& path,
                            bool to_goal = true) {
  ASSERT_GE(plan.states.size(), 2u);
  EXPECT_EQ(plan.states.front().moving_leg, -1);
  EXPECT_LT((plan.states.front().base_position - path.front().p).norm(), 1e-9);
  if (to_goal) {
    EXPECT_LE((plan.states.back().base_position - path.back().p).head<2>().norm(),
              PlannerConfig().base_shift.max_base_shift_m + 1e-9);
  }
  const StanceChecker stance = [&] {
    StanceChecker checker(Robot(), Rules());
    checker.SetTerrain(&world.terrain);
    return checker;
  }();
  PlanCheckConfig config = PlanCheckConfig::FromConfigs(Robot(), Equilibrium(), Rules());
  config.torque_limit_Nm = stance.TorqueCeiling() + 1e-6;
  const PlanCheckReport report = CheckPlan(Robot(), world.terrain, world.surfaces, plan, config);
  std::string violations;
  for (const PlanViolation& v : report.violations) {
    violations += "\n  state " + std::to_string(v.state) + ": " + v.check + ": " + v.detail;
  }
  EXPECT_TRUE(report.ok) << report.Summary() << violations;
  for (std::size_t k = 1; k < plan.states.size(); ++k) {
    const StanceVerdict v = stance.CheckStep(plan.states[k - 1], plan.states[k]);
    EXPECT_TRUE(v.ok()) << "state " << k << ": " << v.Describe();
  }
}

}  // namespace rbcp::test
