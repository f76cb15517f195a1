// Plans footsteps for ANYmal B along a straight 1 m trunk path on the installed flat_ground
// scenario with the installed rbcp libraries and config; prints the steps and the first feet.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <rbcp/affordance/affordance_config.h>
#include <rbcp/affordance/affordance_extractor.h>
#include <rbcp/contact_planner/contact_planner.h>
#include <rbcp/contact_planner/contact_planner_config.h>
#include <rbcp/equilibrium/config.h>
#include <rbcp/limb_database/limb_database.h>
#include <rbcp/stance/stance_config.h>
#include <rbcp/robot/robot_model.h>
#include <rbcp/scenario/scenario.h>

int main() {
  try {
    const std::string config = RBCP_CONFIG_DIR;
    const rbcp::RobotModel robot = rbcp::RobotModel::LoadDefault(config);
    const rbcp::LimbDatabase database = rbcp::LimbDatabase::LoadOrBuild(
        robot, rbcp::LimbDatabase::DefaultRobotFiles(config), rbcp::LimbDatabaseConfig::LoadFile(config + "/limb_database.yaml"));
    const rbcp::Scenario scenario = rbcp::LoadScenario(config + "/scenarios/flat_ground.yaml");
    rbcp::AffordanceExtractor extractor(rbcp::AffordanceConfig::LoadFile(config + "/affordance.yaml"));
    const std::vector<rbcp::AffordanceSurface> surfaces = extractor.Extract(scenario.terrain_mesh);

    rbcp::ContactPlanner planner(robot, database, rbcp::EquilibriumConfig::LoadFile(config + "/equilibrium.yaml"),
                                 rbcp::ContactPlannerConfig::LoadFile(config + "/contact_planner.yaml"),
                                 rbcp::StanceConfig::LoadFile(config + "/stance.yaml"));
    planner.SetTerrain(scenario.terrain_mesh, surfaces);
    // The floor's top is at z = 0: the trunk at its nominal height, 1 m straight ahead in 10 s.
    std::vector<rbcp::RootPathSample> path;
    for (int i = 0; i <= 100; ++i) {
      rbcp::RootPathSample s;
      s.t = 0.1 * i;
      s.p = Eigen::Vector3d(0.01 * i, 0.0, robot.NominalBaseHeight());
      s.v = Eigen::Vector3d(0.1, 0.0, 0.0);
      path.push_back(s);
    }
    const rbcp::ContactPlanResult result = planner.Plan(path);
    if (!result.ok) {
      std::printf("plan_steps: no plan: %s\n", result.reason.c_str());
      return 1;
    }
    const rbcp::WholeBodyState& last = result.plan.states.back();
    std::printf("plan_steps: %d steps over 1 m, %zu surfaces, base ends at x = %.3f m, reached goal: %s\n", result.steps,
                surfaces.size(), last.base_position.x(), result.reached_goal ? "yes" : "no");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plan_steps: error: %s\n", e.what());
    return 2;
  }
}
