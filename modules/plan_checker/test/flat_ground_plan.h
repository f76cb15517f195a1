#pragma once
// A hand-built valid contact plan on flat_ground and the world it is checked in.

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/config.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "rbcp/plan_checker/plan_checker.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp::test {

inline std::string ConfigDir() { return std::string(RBCP_SOURCE_DIR) + "/config"; }
inline std::string ScenarioPath(const std::string& name) { return ConfigDir() + "/scenarios/" + name + ".yaml"; }

/// The flat_ground scenario, the robot, its contact surfaces and the planners' thresholds,
/// loaded once per test program.
struct FlatGroundWorld {
  Scenario scenario;
  RobotModel robot;
  std::vector<AffordanceSurface> surfaces;
  PlanCheckConfig config;

  static const FlatGroundWorld& Get() {
    static const FlatGroundWorld world = [] {
      Scenario scenario = LoadScenario(ScenarioPath("flat_ground"));
      RobotModel robot = RobotModel::LoadDefault(ConfigDir());
      AffordanceExtractor extractor(AffordanceConfig::LoadFile(ConfigDir() + "/affordance.yaml"));
      std::vector<AffordanceSurface> surfaces = extractor.Extract(scenario.terrain_mesh);
      PlanCheckConfig config =
          PlanCheckConfig::FromConfigs(robot, EquilibriumConfig::LoadFile(ConfigDir() + "/equilibrium.yaml"),
                                       StanceRules::LoadFromDir(ConfigDir()));
      return FlatGroundWorld{std::move(scenario), std::move(robot), std::move(surfaces), config};
    }();
    return world;
  }
};

/// Sets every leg's joints by inverse kinematics so the feet stay where `state.feet` says.
inline void SolveJoints(const RobotModel& robot, WholeBodyState& state) {
  const Eigen::Isometry3d base_W = BasePose(state);
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d p_B = base_W.inverse() * state.feet[static_cast<std::size_t>(Index(leg))].position;
    const IkResult ik = robot.SolveLegIk(leg, p_B);
    RBCP_CHECK(ik.ok(), std::string(LegName(leg)) + ": " + ik.reason);
    SetLegJoints(state.joints, leg, ik.q);
  }
}

/// The robot standing at the origin in its reference configuration at the nominal base height,
/// then a crawl: each step one leg moves `step_length` forward, in the order LF, RH, RF, LH
/// (`steps` steps). Before each step the base moves (four feet down) so that the whole-body CoM
/// projects half-way from the centroid of the four feet to the centroid of the three stance feet.
inline ContactPlan BuildFlatGroundPlan(const RobotModel& robot, int steps = 8, double step_length = 0.06) {
  ContactPlan plan;
  WholeBodyState start;
  start.base_position = Eigen::Vector3d(0.0, 0.0, robot.NominalBaseHeight());
  start.joints = robot.ReferenceConfiguration();
  for (Leg leg : kAllLegs) {
    FootContact& foot = start.feet[static_cast<std::size_t>(Index(leg))];
    foot.position = start.base_position + robot.FootPosition(leg, LegJoints(start.joints, leg));
    foot.normal = Eigen::Vector3d::UnitZ();
  }
  plan.states.push_back(start);

  const std::array<Leg, 4> order = {Leg::kLF, Leg::kRH, Leg::kRF, Leg::kLH};
  for (int k = 0; k < steps; ++k) {
    const Leg swing = order[static_cast<std::size_t>(k % 4)];
    WholeBodyState state = plan.states.back();
    state.moving_leg = Index(swing);
    state.feet[static_cast<std::size_t>(Index(swing))].position.x() += step_length;
    Eigen::Vector2d all = Eigen::Vector2d::Zero(), stance = Eigen::Vector2d::Zero();
    for (Leg leg : kAllLegs) {
      const Eigen::Vector2d p = state.feet[static_cast<std::size_t>(Index(leg))].position.head<2>();
      all += p / 4.0;
      if (leg != swing) stance += p / 3.0;
    }
    const Eigen::Vector2d target = all + 0.5 * (stance - all);
    for (int iteration = 0; iteration < 4; ++iteration) {
      SolveJoints(robot, state);
      const Eigen::Vector3d com_W = BasePose(state) * robot.CenterOfMass(state.joints);
      state.base_position.head<2>() += target - com_W.head<2>();
    }
    SolveJoints(robot, state);
    plan.states.push_back(state);
  }
  return plan;
}

/// The (state, check) pairs of a report's violations.
inline std::set<std::pair<int, std::string>> ViolationSet(const PlanCheckReport& report) {
  std::set<std::pair<int, std::string>> out;
  for (const auto& v : report.violations) out.emplace(v.state, v.check);
  return out;
}

inline std::string Describe(const PlanCheckReport& report) {
  std::string out = report.Summary();
  for (const auto& v : report.violations) {
    out += "\n  state " + std::to_string(v.state) + ": " + v.check + ": " + v.detail;
  }
  return out;
}

}  // namespace rbcp::test
