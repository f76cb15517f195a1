#pragma once
// Shared fixtures of the contact planner tests: the robot, a small limb database cached under the
// test temporary folder, scenario worlds with their contact surfaces and root paths, and an
// independent plan checker built on the robot, equilibrium and collision libraries.

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/collision/robot_terrain_collision.h"
#include "rbcp/contact_planner/contact_planner.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/stance_torques.h"
#include "rbcp/equilibrium/static_equilibrium.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/root_planner.h"
#include "rbcp/scenario/scenario.h"

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

/// Independent verification of a plan against its world and root path.
inline void ExpectValidPlan(const ContactPlan& plan, const World& world, const std::vector<RootPathSample>& path,
                            bool to_goal = true) {
  const RobotModel& robot = Robot();
  const ContactPlannerConfig& config = PlannerConfig();
  const EquilibriumConfig& eq = Equilibrium();
  const double torque_limit = config.torque_limit_fraction * robot.ContinuousTorqueLimit() + 1e-6;
  RobotTerrainCollision collision(robot, world.terrain);
  StaticEquilibrium equilibrium(robot.TotalMass(), eq);
  ASSERT_GE(plan.states.size(), 2u);
  EXPECT_EQ(plan.states.front().moving_leg, -1);
  EXPECT_LT((plan.states.front().base_position - path.front().p).norm(), 1e-9);
  if (to_goal) {
    EXPECT_LE((plan.states.back().base_position - path.back().p).head<2>().norm(),
              config.base_shift.max_base_shift_m + 1e-9);
  }

  auto contacts = [](const WholeBodyState& s, int skip) {
    std::vector<ContactPoint> c;
    for (int i = 0; i < kNumLegs; ++i) {
      if (i != skip) c.push_back({s.feet[static_cast<std::size_t>(i)].position, s.feet[static_cast<std::size_t>(i)].normal});
    }
    return c;
  };
  auto positions = [](const std::vector<ContactPoint>& c) {
    std::vector<Eigen::Vector3d> p;
    for (const auto& k : c) p.push_back(k.position);
    return p;
  };
  auto torques_ok = [&](const Eigen::Isometry3d& base, const JointVector& q, const WholeBodyState& s, int skip,
                        const Eigen::Vector3d& com) {
    ForceDistributionParams params;
    params.friction = eq.friction;
    params.min_normal_force_N = config.stance_min_normal_force_N;
    const StanceTorques t = ComputeStanceTorques(robot, base, q, StanceFeet(s.feet, skip), com, params);
    return t.balanced && t.max_abs_Nm <= torque_limit;
  };

  for (std::size_t k = 0; k < plan.states.size(); ++k) {
    SCOPED_TRACE("state " + std::to_string(k));
    const WholeBodyState& s = plan.states[k];
    const Eigen::Isometry3d base = BasePose(s);
    const JointVector q = s.joints;
    for (Leg leg : kAllLegs) {
      const FootContact& foot = s.feet[static_cast<std::size_t>(Index(leg))];
      // Forward kinematics puts the foot contact point on the contact.
      EXPECT_LT((base * robot.FootPosition(leg, LegJoints(q, leg)) - foot.position).norm(), 1e-6) << LegName(leg);
      EXPECT_TRUE(robot.WithinJointBounds(leg, LegJoints(q, leg))) << LegName(leg);
      // The leg short of straight: within the kinematic margins.
      EXPECT_TRUE(robot.WithinMargins(leg, base.inverse() * foot.position, LegJoints(q, leg),
                                      robot.Margins().max_stance_hip_distance_m + 1e-9))
          << LegName(leg) << " " << (base.inverse() * foot.position - robot.HipPosition(leg)).norm() << " m from its hip";
      // The contact lies on a surface: within 1 mm of its plane and inside its polygon.
      bool on_surface = false;
      for (const AffordanceSurface& surface : world.surfaces) {
        const Eigen::Vector3d n = surface.normal.normalized();
        if (std::abs(n.dot(foot.position - surface.vertices[0])) > 1e-3) continue;
        if ((n - foot.normal).norm() > 1e-9) continue;
        bool inside = true;
        for (std::size_t v = 0; v < surface.vertices.size(); ++v) {
          const Eigen::Vector3d& a = surface.vertices[v];
          const Eigen::Vector3d& b = surface.vertices[(v + 1) % surface.vertices.size()];
          if ((b - a).cross(foot.position - a).dot(n) / (b - a).norm() < -1e-6) inside = false;
        }
        if (inside) on_surface = true;
      }
      EXPECT_TRUE(on_surface) << LegName(leg) << " at " << foot.position.transpose();
    }
    std::array<bool, kNumLegs> in_contact{};
    in_contact.fill(true);
    const CollisionReport hit = collision.CheckRobot(base, q, in_contact);
    EXPECT_FALSE(hit.collision) << hit.first_shape << " / " << hit.obstacle << " " << hit.penetration;
    const CollisionReport self = collision.CheckSelf(q);
    EXPECT_FALSE(self.collision) << self.first_shape << " / " << self.obstacle;
    const Eigen::Vector3d com = base * robot.CenterOfMass(q);
    const EquilibriumResult r = equilibrium.Robustness(contacts(s, -1), com);
    EXPECT_GE(r.robustness_N, eq.robustness_threshold_N) << ToString(r.status) << " " << r.reason;
    EXPECT_TRUE(torques_ok(base, q, s, -1, com));

    if (k == 0) continue;
    const WholeBodyState& prev = plan.states[k - 1];
    // Exactly one leg's contact changes, the moving leg's.
    ASSERT_GE(s.moving_leg, 0);
    ASSERT_LT(s.moving_leg, kNumLegs);
    for (int i = 0; i < kNumLegs; ++i) {
      const double moved = (s.feet[static_cast<std::size_t>(i)].position - prev.feet[static_cast<std::size_t>(i)].position).norm();
      if (i == s.moving_leg) {
        EXPECT_GT(moved, 1e-3);
      } else {
        EXPECT_EQ(moved, 0.0) << "leg " << i;
      }
    }
    // Swing: the CoM stays inside the three-foot support triangle with the margin, with the
    // swing leg at lift-off (previous foot, IK at this base) and at touch-down (this state), and
    // the three-foot stance is balanced within the torque limits.
    const std::vector<ContactPoint> stance = contacts(s, s.moving_leg);
    EXPECT_GE(SupportPolygonMargin(positions(stance), com), eq.support_margin_m - 1e-9);
    EXPECT_TRUE(torques_ok(base, q, s, s.moving_leg, com));
    JointVector q_pre = q;
    const Leg moving = kAllLegs[static_cast<std::size_t>(s.moving_leg)];
    const IkResult ik = robot.SolveLegIk(moving, base.inverse() * prev.feet[static_cast<std::size_t>(s.moving_leg)].position);
    ASSERT_TRUE(ik.ok()) << ik.reason;
    SetLegJoints(q_pre, moving, ik.q);
    const Eigen::Vector3d com_pre = base * robot.CenterOfMass(q_pre);
    EXPECT_GE(SupportPolygonMargin(positions(stance), com_pre), eq.support_margin_m - 1e-9);
    EXPECT_TRUE(torques_ok(base, q_pre, s, s.moving_leg, com_pre));
  }
}

}  // namespace rbcp::test
