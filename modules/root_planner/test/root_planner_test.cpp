#include "rbcp/root_planner/root_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/core/angle.h"
#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/test_support/error_of.h"
#include "test_terrains.h"

namespace rbcp {
namespace {

using test::kConfigDir;
using test_support::ErrorOf;

const RobotModel& Robot() {
  static const RobotModel robot = RobotModel::LoadDefault(kConfigDir);
  return robot;
}

const RootPlannerConfig& DefaultConfig() {
  static const RootPlannerConfig config = RootPlannerConfig::LoadFile(kConfigDir + "/root_planner.yaml", kConfigDir);
  return config;
}

// Checks a found path: it starts and ends at the requested states, respects the bounds, and
// every sample (every time_step) satisfies the reachability condition.
void ExpectSoundPath(const RootPlanner& planner, const TriangleMesh& terrain,
                     const std::vector<AffordanceSurface>& surfaces, const RootPlanResult& result,
                     const Eigen::Vector3d& start, double start_yaw, const Eigen::Vector3d& goal, double goal_yaw) {
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_TRUE(result.reason.empty());
  ASSERT_GE(result.samples.size(), 2u);
  const RootPlannerConfig& config = planner.config();
  const auto& first = result.samples.front();
  const auto& last = result.samples.back();
  EXPECT_LT((first.p - start).norm(), 1e-9);
  EXPECT_LT(first.v.norm(), 1e-9);
  EXPECT_NEAR(WrapAngle(first.yaw - start_yaw), 0.0, 1e-9);
  EXPECT_LT((last.p - goal).norm(), 1e-6);
  EXPECT_LT(last.v.norm(), 1e-6);
  EXPECT_NEAR(WrapAngle(last.yaw - goal_yaw), 0.0, 1e-6);
  EXPECT_NEAR(last.t, result.path.Duration(), 1e-9);
  EXPECT_LE(result.path.Duration(), result.duration_before_shortcut_s + 1e-9);
  ReachabilityChecker checker = planner.MakeChecker(terrain, surfaces);
  for (std::size_t i = 0; i < result.samples.size(); ++i) {
    const RootPathSample& s = result.samples[i];
    if (i > 0 && i + 1 < result.samples.size()) {
      EXPECT_NEAR(s.t - result.samples[i - 1].t, config.time_step, 1e-9);
    }
    if (i > 0) {
      EXPECT_LE(std::abs(WrapAngle(s.yaw - result.samples[i - 1].yaw)),
                config.max_yaw_rate * (s.t - result.samples[i - 1].t) + 1e-9);
    }
    const ReachabilityReport report = checker.Check(s.p, s.yaw);
    EXPECT_TRUE(report.Valid()) << "t " << s.t << ": " << report.Reason();
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(s.v[k]), config.limits.Axis(k).v_max + 1e-9);
      EXPECT_LE(std::abs(s.a[k]), config.limits.Axis(k).a_max + 1e-9);
    }
  }
  // The velocity is the derivative of the position (no jumps between pieces).
  const auto fine = result.path.SampleEvery(0.01);
  for (std::size_t i = 1; i < fine.size(); ++i) {
    const double dt = fine[i].t - fine[i - 1].t;
    EXPECT_LT((fine[i].p - fine[i - 1].p - 0.5 * dt * (fine[i].v + fine[i - 1].v)).norm(), 0.5 * dt * dt * 2.0 * 5.0 + 1e-9);
    EXPECT_LT((fine[i].v - fine[i - 1].v).norm(), dt * 5.2 + 1e-9);
  }
}

TEST(RootPlannerConfigTest, TheShippedFileHoldsTheDefaults) {
  EXPECT_EQ(DifferingFields(DefaultConfig(), RootPlannerConfig()), std::vector<std::string>{});
}

TEST(RootPlannerConfigTest, LoadsTheCommittedFileStrictly) {
  const RootPlannerConfig& config = DefaultConfig();
  EXPECT_EQ(config.limits.horizontal.v_max, 0.3);
  EXPECT_EQ(config.limits.horizontal.a_max, 1.0);
  EXPECT_EQ(config.time_step, 0.05);
  EXPECT_EQ(config.trunk.keel_bottom_z, -0.325);
  for (const auto& rom : config.roms) EXPECT_GT(rom.Volume(), 0.1);
  YAML::Node node = YAML::LoadFile(kConfigDir + "/root_planner.yaml");
  node["unexpected"] = 1;
  EXPECT_THROW(RootPlannerConfig::Load(YamlMap(node, "test"), kConfigDir), InputError);
  node = YAML::LoadFile(kConfigDir + "/root_planner.yaml");
  node["time_step"] = -0.05;
  EXPECT_THROW(RootPlannerConfig::Load(YamlMap(node, "test"), kConfigDir), InputError);
  node = YAML::LoadFile(kConfigDir + "/root_planner.yaml");
  node["rom_folder"] = "no/such/folder";
  EXPECT_THROW(RootPlannerConfig::Load(YamlMap(node, "test"), kConfigDir), InputError);
  node = YAML::LoadFile(kConfigDir + "/root_planner.yaml");
  node["limits"]["vertical"]["a_max"] = 0.0;
  EXPECT_EQ(ErrorOf([&] { RootPlannerConfig::Load(YamlMap(node, "test"), kConfigDir); }),
            "test: limits: vertical: 'a_max': expected v_max and a_max both > 0 (z moves) or both 0 (z fixed), got 0 "
            "with v_max 0.3");
  node["limits"]["vertical"]["v_max"] = 0.0;
  EXPECT_TRUE(RootPlannerConfig::Load(YamlMap(node, "test"), kConfigDir).limits.VerticalFixed());
}

struct ScenarioCase {
  Scenario scenario;
  std::vector<AffordanceSurface> surfaces;
  Eigen::Vector3d start;
  Eigen::Vector3d goal;
};

ScenarioCase LoadCase(const std::string& name, const RootPlanner& planner) {
  ScenarioCase c;
  c.scenario = LoadScenario(kConfigDir + "/scenarios/" + name + ".yaml");
  AffordanceExtractor extractor(AffordanceConfig::LoadFile(kConfigDir + "/affordance.yaml"));
  c.surfaces = extractor.Extract(c.scenario.terrain_mesh);
  c.start = *planner.StandingPosition(c.scenario.terrain_mesh, c.scenario.start.position);
  c.goal = *planner.StandingPosition(c.scenario.terrain_mesh, c.scenario.goal.position);
  return c;
}

class ScenarioPlanningTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ScenarioPlanningTest, FindsSoundPathsForSeveralSeeds) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const ScenarioCase c = LoadCase(GetParam(), planner);
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const RootPlanResult result = planner.Plan(c.scenario.terrain_mesh, c.surfaces, c.start, c.scenario.start.yaw,
                                               c.goal, c.scenario.goal.yaw, seed, 20.0);
    ExpectSoundPath(planner, c.scenario.terrain_mesh, c.surfaces, result, c.start, c.scenario.start.yaw, c.goal,
                    c.scenario.goal.yaw);
  }
}

INSTANTIATE_TEST_SUITE_P(BenchmarkScenarios, ScenarioPlanningTest,
                         ::testing::Values("flat_ground", "slalom_debris", "plinth", "darpa_rubble"));

// Shortcuts cannot cut across the plinth's steps (they are straight in 3D), so the path keeps the
// detours of the tree to either side; straightening in the horizontal plane takes it to the centre
// line between the start and the goal (both at y = 0) and keeps it sound.
TEST(RootPlannerTest, StraighteningDrawsThePlinthPathToTheCentreLine) {
  RootPlannerConfig unstraightened = DefaultConfig();
  unstraightened.straighten_iterations = 0;
  const RootPlanner planner(Robot(), DefaultConfig());
  const RootPlanner raw_planner(Robot(), unstraightened);
  const ScenarioCase c = LoadCase("plinth", planner);
  const auto max_lateral = [](const RootPlanResult& r) {
    double m = 0.0;
    for (const RootPathSample& s : r.samples) m = std::max(m, std::abs(s.p.y()));
    return m;
  };
  double raw_worst = 0.0;
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const RootPlanResult raw = raw_planner.Plan(c.scenario.terrain_mesh, c.surfaces, c.start, c.scenario.start.yaw,
                                                c.goal, c.scenario.goal.yaw, seed, 20.0);
    const RootPlanResult straight = planner.Plan(c.scenario.terrain_mesh, c.surfaces, c.start, c.scenario.start.yaw,
                                                 c.goal, c.scenario.goal.yaw, seed, 20.0);
    ASSERT_TRUE(raw.ok()) << raw.reason;
    ExpectSoundPath(planner, c.scenario.terrain_mesh, c.surfaces, straight, c.start, c.scenario.start.yaw, c.goal,
                    c.scenario.goal.yaw);
    EXPECT_LT(max_lateral(straight), 0.05);
    EXPECT_LE(straight.path.Duration(), 1.1 * raw.path.Duration() + 1e-9);
    raw_worst = std::max(raw_worst, max_lateral(raw));
  }
  EXPECT_GT(raw_worst, 0.1);  // without straightening the detours are there
}

TEST(RootPlannerTest, SameSeedSamePath) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const ScenarioCase c = LoadCase("darpa_rubble", planner);
  const RootPlanResult a = planner.Plan(c.scenario.terrain_mesh, c.surfaces, c.start, 0.0, c.goal, 0.0, 42, 20.0);
  const RootPlanResult b = planner.Plan(c.scenario.terrain_mesh, c.surfaces, c.start, 0.0, c.goal, 0.0, 42, 20.0);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a.iterations, b.iterations);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  for (std::size_t i = 0; i < a.samples.size(); ++i) {
    EXPECT_EQ(a.samples[i].p, b.samples[i].p);
    EXPECT_EQ(a.samples[i].v, b.samples[i].v);
    EXPECT_EQ(a.samples[i].yaw, b.samples[i].yaw);
  }
}

TEST(RootPlannerTest, TurnsFromTheStartYawToTheGoalYawWithoutJumps) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms ground = test::MakePlatforms({{-2.0, 3.0}});
  const Eigen::Vector3d start(0.0, 0.0, Robot().NominalBaseHeight());
  const Eigen::Vector3d goal(1.0, 0.5, Robot().NominalBaseHeight());
  const RootPlanResult result = planner.Plan(ground.terrain, ground.surfaces, start, 1.0, goal, -2.0, 5, 20.0);
  ExpectSoundPath(planner, ground.terrain, ground.surfaces, result, start, 1.0, goal, -2.0);
  // Between the validation samples the yaw rate stays moderate too (no swing round).
  const auto fine = result.path.SampleEvery(0.001);
  for (std::size_t i = 1; i < fine.size(); ++i) {
    EXPECT_LT(std::abs(WrapAngle(fine[i].yaw - fine[i - 1].yaw)), 0.03) << fine[i].t;
  }
}

/// Ground x in [-3, 0], a 1.5 m pit, an island x in [1.5, 3].
test::Platforms PitAndIsland() { return test::MakePlatforms({{-3.0, 0.0}, {1.5, 3.0}}); }

TEST(RootPlannerTest, IslandBeyondAWidePitIsUnreachableBeforeAnySearch) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms world = PitAndIsland();
  const double h = Robot().NominalBaseHeight();
  const RootPlanResult result =
      planner.Plan(world.terrain, world.surfaces, {-1.0, 0.0, h}, 0.0, {2.2, 0.0, h}, 0.0, 1, 5.0);
  EXPECT_EQ(result.status, RootPlanStatus::kGoalUnreachable);
  EXPECT_EQ(ToString(result.status), "goal_unreachable");
  EXPECT_NE(result.reason.find("no chain of contact surfaces"), std::string::npos) << result.reason;
  EXPECT_TRUE(result.samples.empty());
  EXPECT_EQ(result.iterations, 0);
}

TEST(RootPlannerTest, IslandBeyondAWidePitHasNoPathWhenTheGapIsNotRuledOut) {
  // With surfaces joined across any gap the search runs, and finds no path within its budget.
  RootPlannerConfig config = DefaultConfig();
  config.max_surface_gap = 2.0;
  const RootPlanner planner(Robot(), config);
  const test::Platforms world = PitAndIsland();
  const double h = Robot().NominalBaseHeight();
  const RootPlanResult result =
      planner.Plan(world.terrain, world.surfaces, {-1.0, 0.0, h}, 0.0, {2.2, 0.0, h}, 0.0, 1, 0.5);
  EXPECT_EQ(result.status, RootPlanStatus::kTimeout);
  EXPECT_NE(result.reason.find("no path"), std::string::npos) << result.reason;
  EXPECT_TRUE(result.samples.empty());
  EXPECT_GT(result.iterations, 0);
}

/// A planner of at most 60 iterations whose surfaces are joined across any gap: over the pit
/// between PitAndIsland()'s two platforms the search runs and finds no path.
RootPlanner SixtyIterationsAcrossAnyGap() {
  RootPlannerConfig config = DefaultConfig();
  config.max_surface_gap = 2.0;
  config.max_iterations = 60;
  return RootPlanner(Robot(), config);
}

TEST(RootPlannerTest, TheSearchEndsAfterItsIterationLimitNotOnTheClock) {
  // A generous budget: the search ends after max_iterations, every time the same way.
  const RootPlanner planner = SixtyIterationsAcrossAnyGap();
  const test::Platforms world = PitAndIsland();
  const double h = Robot().NominalBaseHeight();
  for (int run = 0; run < 2; ++run) {
    const RootPlanResult result =
        planner.Plan(world.terrain, world.surfaces, {-1.0, 0.0, h}, 0.0, {2.2, 0.0, h}, 0.0, 3, 60.0);
    EXPECT_EQ(result.status, RootPlanStatus::kTimeout);
    EXPECT_EQ(result.iterations, 60);
    EXPECT_NE(result.reason.find("no path found within 60 iterations"), std::string::npos) << result.reason;
  }
}

TEST(RootPlannerTest, ARequestsIterationLimitBoundsItsSearchBelowTheConfigs) {
  const RootPlanner planner = SixtyIterationsAcrossAnyGap();
  const test::Platforms world = PitAndIsland();
  const double h = Robot().NominalBaseHeight();
  RootPlanRequest request;
  request.start.p = {-1.0, 0.0, h};
  request.goal = {2.2, 0.0, h};
  request.seed = 3;
  request.time_budget_s = 60.0;
  request.max_iterations = 25;
  RootPlanResult result = planner.Plan(world.terrain, world.surfaces, request);
  EXPECT_EQ(result.status, RootPlanStatus::kTimeout);
  EXPECT_EQ(result.iterations, 25);
  EXPECT_NE(result.reason.find("no path found within 25 iterations"), std::string::npos) << result.reason;
  // Above the config's limit, the config's holds.
  request.max_iterations = 1000;
  result = planner.Plan(world.terrain, world.surfaces, request);
  EXPECT_EQ(result.iterations, 60);
}

TEST(RootPlannerTest, AGoalAtTheStartWithAnotherHeadingTurnsOnTheSpot) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms ground = test::MakePlatforms({{-2.0, 2.0}});
  const Eigen::Vector3d at(0.0, 0.0, Robot().NominalBaseHeight());
  const RootPlanResult result = planner.Plan(ground.terrain, ground.surfaces, at, 0.2, at, 2.0, 1, 1.0);
  ASSERT_TRUE(result.ok()) << result.reason;
  ASSERT_GE(result.samples.size(), 2u);
  EXPECT_GT(result.path.Duration(), 1.0);
  for (const RootPathSample& s : result.samples) {
    EXPECT_LT((s.p - at).norm(), 1e-12);
    EXPECT_EQ(s.v.norm(), 0.0);
  }
  EXPECT_NEAR(result.samples.front().yaw, 0.2, 1e-9);
  EXPECT_NEAR(result.samples.back().yaw, 2.0, 1e-9);
  // The heading turns one way, monotonically.
  for (std::size_t i = 1; i < result.samples.size(); ++i) {
    EXPECT_GE(result.samples[i].yaw, result.samples[i - 1].yaw - 1e-12);
  }
  // The same pose and heading: a valid, trivial request.
  EXPECT_TRUE(planner.Plan(ground.terrain, ground.surfaces, at, 0.2, at, 0.2, 1, 1.0).ok());
}

TEST(RootPlannerTest, InvalidStartOrGoalIsReported) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms world = PitAndIsland();
  const double h = Robot().NominalBaseHeight();
  // Goal above the middle of the pit: no leg reaches ground.
  const RootPlanResult over_pit =
      planner.Plan(world.terrain, world.surfaces, {-1.0, 0.0, h}, 0.0, {0.75, 0.0, h}, 0.0, 1, 1.0);
  EXPECT_EQ(over_pit.status, RootPlanStatus::kGoalInvalid);
  EXPECT_EQ(over_pit.reason, "goal: no contact surface in reach of LF, RF, LH, RH");
  // Start sunk into the ground.
  const RootPlanResult sunk = planner.Plan(world.terrain, world.surfaces, {-1.0, 0.0, 0.2}, 0.0, {-2.0, 0.0, h}, 0.0, 1, 1.0);
  EXPECT_EQ(sunk.status, RootPlanStatus::kStartInvalid);
  EXPECT_NE(sunk.reason.find("trunk collides"), std::string::npos) << sunk.reason;
  EXPECT_EQ(ToString(sunk.status), "start_invalid");
}

// The lowest height at `xy` (heading 0), by centimetres below `from`, where the reachability
// condition holds.
double LowestValidHeight(ReachabilityChecker& checker, const Eigen::Vector2d& xy, double from) {
  double lowest = from;
  while (checker.Check({xy.x(), xy.y(), lowest - 0.01}, 0.0).Valid()) lowest -= 0.01;
  return lowest;
}

TEST(RootPlannerTest, AStartALittleLowBeginsItsPathAtTheLowestValidHeight) {
  // A robot standing lower than the conservative trunk volume allows: its path begins at most
  // 5 cm higher, at the lowest height (centimetre steps) where the reachability condition holds.
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms ground = test::MakePlatforms({{-3.0, 3.0}});
  const double h = Robot().NominalBaseHeight();
  ReachabilityChecker checker = planner.MakeChecker(ground.terrain, ground.surfaces);
  const double lowest = LowestValidHeight(checker, {-1.0, 0.0}, h);
  const double low = lowest - 0.03;
  ASSERT_TRUE(checker.Check({-1.0, 0.0, low}, 0.0).trunk_collision);
  int raise_cm = 1;
  while (!checker.Check({-1.0, 0.0, low + 0.01 * raise_cm}, 0.0).Valid()) ++raise_cm;
  EXPECT_LE(raise_cm, 3);
  const RootPlanResult result = planner.Plan(ground.terrain, ground.surfaces, {-1.0, 0.0, low}, 0.0, {1.0, 0.0, h}, 0.0, 1, 5.0);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_NEAR(result.samples.front().p.z(), low + 0.01 * raise_cm, 1e-9);
  EXPECT_NEAR(result.samples.front().p.x(), -1.0, 1e-9);
  // Deeper than that, the start stays invalid.
  const RootPlanResult deep =
      planner.Plan(ground.terrain, ground.surfaces, {-1.0, 0.0, lowest - 0.07}, 0.0, {1.0, 0.0, h}, 0.0, 1, 5.0);
  EXPECT_EQ(deep.status, RootPlanStatus::kStartInvalid) << deep.reason;
}

TEST(RootPlannerTest, AMeasuredStartWhereTheConditionFailsIsJoinedToTheNearestStateWhereItHolds) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms ground = test::MakePlatforms({{-3.0, 3.0}});
  const double h = Robot().NominalBaseHeight();
  ReachabilityChecker checker = planner.MakeChecker(ground.terrain, ground.surfaces);
  // Crouched lower than a 5 cm raise can mend.
  const Eigen::Vector3d crouched(-1.0, 0.0, LowestValidHeight(checker, {-1.0, 0.0}, h) - 0.10);
  for (int cm = 0; cm <= 5; ++cm) ASSERT_FALSE(checker.Check(crouched + Eigen::Vector3d(0, 0, 0.01 * cm), 0.0).Valid());
  RootPlanRequest request;
  request.start.p = crouched;
  request.goal = {1.0, 0.0, h};
  request.time_budget_s = 5.0;
  const RootPlanResult requested = planner.Plan(ground.terrain, ground.surfaces, request);
  EXPECT_EQ(requested.status, RootPlanStatus::kStartInvalid) << "a requested start must satisfy the condition";

  request.start_is_measured = true;
  const RootPlanResult measured = planner.Plan(ground.terrain, ground.surfaces, request);
  ASSERT_TRUE(measured.ok()) << measured.reason;
  EXPECT_LT((measured.samples.front().p - crouched).norm(), 1e-9) << "the path starts where the robot stands";
  EXPECT_LT(measured.samples.front().v.norm(), 1e-9);
  EXPECT_GT(measured.start_join_m, 0.0);
  EXPECT_LE(measured.start_join_m, kMaxStartJoinM + 1e-9);
  EXPECT_LT((measured.samples.back().p - request.goal).norm(), 1e-6);
  // The joining move is the path's first segment, straight and at rest at both ends; the rest
  // of the path satisfies the condition.
  ASSERT_GE(measured.path.Segments().size(), 2u);
  const double join_end = measured.path.Segments().front().Duration();
  const RootPathSample joined = measured.path.Sample(join_end);
  EXPECT_NEAR((joined.p - crouched).norm(), measured.start_join_m, 1e-9);
  EXPECT_LT(joined.v.norm(), 1e-9);
  for (const RootPathSample& s : measured.samples) {
    if (s.t >= join_end - 1e-9) {
      EXPECT_TRUE(checker.Check(s.p, s.yaw).Valid()) << "t " << s.t;
    }
  }

  // Over the middle of a wide pit no state within reach of a short move holds: still refused.
  const test::Platforms pit = test::MakePlatforms({{-3.0, -1.0}, {1.0, 3.0}});
  request.start.p = {0.0, 0.0, h};
  request.goal = {2.0, 0.0, h};
  const RootPlanResult over_pit = planner.Plan(pit.terrain, pit.surfaces, request);
  EXPECT_EQ(over_pit.status, RootPlanStatus::kStartInvalid) << over_pit.reason;
  EXPECT_EQ(over_pit.reason, "start: no contact surface in reach of LF, RF, LH, RH");
}

TEST(RootPlannerTest, GoalsTowardAGoalBeyondAGapAreOnlyWhereTheRobotCanWalkTo) {
  // A platform the robot stands on and, 1 m beyond it (more than a step bridges), an island of
  // the map that reaches the goal: the island is no goal; the near platform's end is.
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms world = test::MakePlatforms({{-3.0, 0.0}, {1.0, 3.0}});
  const std::vector<Eigen::Vector3d> goals =
      planner.GoalsToward(world.terrain, world.surfaces, {-2.0, 0.0}, {2.5, 0.0}, 0.0, GoalsTowardOptions{});
  ASSERT_FALSE(goals.empty());
  for (const Eigen::Vector3d& g : goals) EXPECT_LT(g.x(), 0.0) << "a goal on the island at x " << g.x();
  // Standing on the island, the goal itself is one.
  const std::vector<Eigen::Vector3d> on_island =
      planner.GoalsToward(world.terrain, world.surfaces, {1.5, 0.0}, {2.5, 0.0}, 0.0, GoalsTowardOptions{});
  ASSERT_FALSE(on_island.empty());
  EXPECT_NEAR(on_island.front().x(), 2.5, 1e-9);
}

TEST(RootPlannerTest, AMeasuredBaseInsideTheTerrainOrOverNoneIsNamed) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms world = PitAndIsland();
  const double h = Robot().NominalBaseHeight();
  EXPECT_FALSE(planner.CheckMeasuredBase(world.terrain, {-1.0, 0.0, h}).has_value());
  const auto inside = planner.CheckMeasuredBase(world.terrain, {-1.0, 0.0, -0.1});
  ASSERT_TRUE(inside.has_value());
  EXPECT_EQ(inside->kind, MeasuredBaseProblem::Kind::kInsideTerrain);
  EXPECT_DOUBLE_EQ(inside->terrain_top_z, 0.0);
  EXPECT_EQ(inside->Describe(), "the measured base at (-1.00, 0.00, -0.10) is inside the terrain, which rises to z 0.00 there");
  const auto over_pit = planner.CheckMeasuredBase(world.terrain, {0.75, 0.0, h});
  ASSERT_TRUE(over_pit.has_value());
  EXPECT_EQ(over_pit->kind, MeasuredBaseProblem::Kind::kNoTerrain);
}

TEST(RootPlannerTest, PlansFromAMovingStart) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms ground = test::MakePlatforms({{-2.0, 3.0}});
  RootPlanRequest request;
  request.start.p = {0.0, 0.0, Robot().NominalBaseHeight()};
  request.start.v = {0.04, 0.01, 0.0};  // below the yaw blend speed: the yaw is free to differ from the heading
  request.start_yaw = 0.1;
  request.goal = {1.5, -0.3, Robot().NominalBaseHeight()};
  request.goal_yaw = 0.0;
  request.seed = 3;
  request.time_budget_s = 20.0;
  const RootPlanResult result = planner.Plan(ground.terrain, ground.surfaces, request);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_LT((result.samples.front().v - request.start.v).norm(), 1e-9);
  EXPECT_NEAR(result.samples.front().yaw, 0.1, 1e-9);
  request.start.v.x() = 0.5;
  EXPECT_EQ(planner.Plan(ground.terrain, ground.surfaces, request).status, RootPlanStatus::kStartInvalid);
}

TEST(RootPlannerTest, ARequestWithBadContentIsAnsweredWithAStatus) {
  const RootPlanner planner(Robot(), DefaultConfig());
  const test::Platforms ground = test::MakePlatforms({{-2.0, 3.0}});
  RootPlanRequest request;
  request.start.p = {0.0, 0.0, Robot().NominalBaseHeight()};
  request.goal = {1.0, std::numeric_limits<double>::quiet_NaN(), Robot().NominalBaseHeight()};
  RootPlanResult result = planner.Plan(ground.terrain, ground.surfaces, request);
  EXPECT_EQ(result.status, RootPlanStatus::kInvalidInput);
  EXPECT_EQ(result.reason, "root plan request: expected finite start and goal, got a non-finite value");
  request.goal.y() = 0.0;
  request.time_budget_s = 0.0;
  result = planner.Plan(ground.terrain, ground.surfaces, request);
  EXPECT_EQ(result.status, RootPlanStatus::kInvalidInput);
  EXPECT_EQ(ToString(result.status) + ": " + result.reason,
            "invalid_input: root plan request: expected a time budget > 0 s, got 0");
}

}  // namespace
}  // namespace rbcp
