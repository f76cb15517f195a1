#include "rbcp/collision/robot_terrain_collision.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <variant>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

const std::string kConfigDir = std::string(RBCP_SOURCE_DIR) + "/config";
constexpr std::array<bool, kNumLegs> kAllStance = {true, true, true, true};
constexpr std::array<bool, kNumLegs> kNoStance = {false, false, false, false};

const RobotModel& Anymal() {
  static const RobotModel model = RobotModel::LoadDefault(kConfigDir);
  return model;
}

const Scenario& LoadNamed(const std::string& name) {
  static std::map<std::string, Scenario> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, LoadScenario(kConfigDir + "/scenarios/" + name + ".yaml")).first;
  return it->second;
}

Eigen::Isometry3d BaseAt(double x, double y, double z) {
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(x, y, z);
  return base;
}

Eigen::Isometry3d Standing(double dz = 0.0) { return BaseAt(0.0, 0.0, Anymal().NominalBaseHeight() + dz); }

bool StartsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

std::set<std::string> TrunkShapeNames() {
  std::set<std::string> names;
  for (const CollisionShape& s : Anymal().CollisionShapes()) {
    if (!s.leg) names.insert(s.name);
  }
  return names;
}

std::set<std::string> RobotShapeNames() {
  std::set<std::string> names;
  for (const CollisionShape& s : Anymal().CollisionShapes()) names.insert(s.name);
  return names;
}

void ExpectSameReport(const CollisionReport& a, const CollisionReport& b) {
  EXPECT_EQ(a.collision, b.collision);
  EXPECT_EQ(a.first_shape, b.first_shape);
  EXPECT_EQ(a.obstacle, b.obstacle);
  EXPECT_EQ(a.penetration, b.penetration);
}

// ---- Flat ground ---------------------------------------------------------------------------------

TEST(RobotTerrainCollision, ReferenceStanceOnFlatGroundIsFree) {
  const RobotTerrainCollision checker(Anymal(), LoadNamed("flat_ground").terrain_mesh);
  const JointVector& q = Anymal().ReferenceConfiguration();
  const CollisionReport report = checker.CheckRobot(Standing(), q, kAllStance);
  EXPECT_FALSE(report.collision) << report.first_shape << " in " << report.obstacle;
  EXPECT_TRUE(report.first_shape.empty());
  EXPECT_FALSE(checker.CheckTrunk(Standing()).collision);
  for (Leg leg : kAllLegs) EXPECT_FALSE(checker.CheckLeg(leg, Standing(), LegJoints(q, leg), true).collision);
}

TEST(RobotTerrainCollision, LoweredRobotCollidesAndNamesTheShape) {
  const RobotTerrainCollision checker(Anymal(), LoadNamed("flat_ground").terrain_mesh);
  const JointVector& q = Anymal().ReferenceConfiguration();
  const CollisionReport report = checker.CheckRobot(Standing(-0.15), q, kAllStance);
  ASSERT_TRUE(report.collision);
  EXPECT_EQ(RobotShapeNames().count(report.first_shape), 1u) << report.first_shape;
  EXPECT_EQ(report.obstacle, "terrain");
  EXPECT_GT(report.penetration, 0.0);
  // The legs sink into the ground; the trunk is still above it at this height.
  EXPECT_EQ(TrunkShapeNames().count(report.first_shape), 0u);
  EXPECT_FALSE(checker.CheckTrunk(Standing(-0.15)).collision);
  const Leg leg = *LegFromName(report.first_shape.substr(0, 2));
  EXPECT_TRUE(checker.CheckLeg(leg, Standing(-0.15), LegJoints(q, leg), true).collision);

  // Lowered further, the belly hits the ground.
  const CollisionReport trunk = checker.CheckTrunk(Standing(-0.35));
  ASSERT_TRUE(trunk.collision);
  EXPECT_EQ(TrunkShapeNames().count(trunk.first_shape), 1u) << trunk.first_shape;
}

TEST(RobotTerrainCollision, SwingFeetTouchingTheGroundCollide) {
  // At the reference stance the foot spheres dip 1.3 mm below the contact plane (the contact
  // point lies on the sphere along the tilted shank axis): allowed in stance, a collision in swing.
  const RobotTerrainCollision checker(Anymal(), LoadNamed("flat_ground").terrain_mesh);
  const JointVector& q = Anymal().ReferenceConfiguration();
  const CollisionReport swing = checker.CheckRobot(Standing(), q, kNoStance);
  ASSERT_TRUE(swing.collision);
  EXPECT_EQ(swing.first_shape, "LF_foot");
  EXPECT_EQ(swing.obstacle, "terrain");
  EXPECT_GT(swing.penetration, 0.0005);
  EXPECT_LT(swing.penetration, 0.003);
  // Only LF in swing: only LF is reported; then RH alone.
  EXPECT_EQ(checker.CheckRobot(Standing(), q, {false, true, true, true}).first_shape, "LF_foot");
  EXPECT_EQ(checker.CheckRobot(Standing(), q, {true, true, true, false}).first_shape, "RH_foot");
  // Lifted by 5 mm the swing feet are clear.
  EXPECT_FALSE(checker.CheckRobot(Standing(0.005), q, kNoStance).collision);
}

TEST(RobotTerrainCollision, StanceFeetMaySinkUpToTheTolerance) {
  const RobotTerrainCollision checker(Anymal(), LoadNamed("flat_ground").terrain_mesh);
  ASSERT_DOUBLE_EQ(checker.Options().foot_tolerance, 0.015);
  const JointVector& q = Anymal().ReferenceConfiguration();
  // 10 mm lower: the spheres sink by ~11.3 mm < 15 mm.
  EXPECT_FALSE(checker.CheckRobot(Standing(-0.010), q, kAllStance).collision);
  // 20 mm lower: ~21.3 mm > 15 mm.
  const CollisionReport deep = checker.CheckRobot(Standing(-0.020), q, kAllStance);
  ASSERT_TRUE(deep.collision);
  EXPECT_EQ(deep.first_shape, "LF_foot");
  EXPECT_GT(deep.penetration, 0.015);
  EXPECT_LT(deep.penetration, 0.025);

  CollisionOptions strict;
  strict.foot_tolerance = 0.0;
  const RobotTerrainCollision strict_checker(Anymal(), LoadNamed("flat_ground").terrain_mesh, strict);
  EXPECT_EQ(strict_checker.CheckRobot(Standing(), q, kAllStance).first_shape, "LF_foot");
}

TEST(RobotTerrainCollision, StanceAdapterTubeEndIsExcluded) {
  // LF foot on the ground 0.2 m ahead of its reference point with the base 0.1 m lower: the shank
  // leans ~51 degrees from vertical, the adapter tube's end dips below the ground.
  const RobotModel& robot = Anymal();
  const Eigen::Isometry3d base = Standing(-0.1);
  const IkResult ik = robot.SolveLegIk(Leg::kLF, robot.ReferenceFootPosition(Leg::kLF) + Eigen::Vector3d(0.2, 0.0, 0.1));
  ASSERT_TRUE(ik.ok()) << ik.reason;
  const TriangleMesh& ground = LoadNamed("flat_ground").terrain_mesh;

  const RobotTerrainCollision checker(robot, ground);
  EXPECT_FALSE(checker.CheckLeg(Leg::kLF, base, ik.q, true).collision);

  CollisionOptions whole_tube;
  whole_tube.adapter_exclusion = 0.0;
  const CollisionReport tube = RobotTerrainCollision(robot, ground, whole_tube).CheckLeg(Leg::kLF, base, ik.q, true);
  ASSERT_TRUE(tube.collision);
  EXPECT_EQ(tube.first_shape, "LF_adapter_tube");

  // The sphere sinks by r (1 - cos 51 deg) ~ 11.7 mm: over a 5 mm tolerance.
  CollisionOptions tight_foot;
  tight_foot.foot_tolerance = 0.005;
  const CollisionReport foot = RobotTerrainCollision(robot, ground, tight_foot).CheckLeg(Leg::kLF, base, ik.q, true);
  ASSERT_TRUE(foot.collision);
  EXPECT_EQ(foot.first_shape, "LF_foot");
  EXPECT_GT(foot.penetration, 0.008);
  EXPECT_LT(foot.penetration, 0.015);
}

// ---- Plinth and walls -----------------------------------------------------------------------------

TEST(RobotTerrainCollision, TrunkInsidePlinthStepCollides) {
  // The plinth top block spans x +-0.29, y +-0.52, z -0.5..0.51. At base z = 0.2 every trunk
  // primitive lies strictly inside it, touching no face.
  const RobotTerrainCollision checker(Anymal(), LoadNamed("plinth").terrain_mesh);
  const CollisionReport inside = checker.CheckTrunk(BaseAt(0.0, 0.0, 0.2));
  ASSERT_TRUE(inside.collision);
  EXPECT_EQ(inside.first_shape, "main_body");
  EXPECT_EQ(inside.obstacle, "terrain");
  EXPECT_NEAR(inside.penetration, 0.51 - (0.2 + 0.08), 1e-9);  // main body centre to the top face
  EXPECT_TRUE(checker.InsideTerrain(Eigen::Vector3d(0.0, 0.0, 0.28)));

  // Crossing the top face.
  EXPECT_TRUE(checker.CheckTrunk(BaseAt(0.0, 0.0, 0.5)).collision);
  // Just above it (belly bumps reach 0.125 m below the base).
  EXPECT_FALSE(checker.CheckTrunk(BaseAt(0.0, 0.0, 0.51 + 0.125 + 0.01)).collision);
}

TEST(RobotTerrainCollision, LegSwungThroughWallCollidesOthersDoNot) {
  // slalom_debris: a 2 cm wall at x 0.522..0.542 across the corridor. The robot stands 0.45 m
  // before it and raises LF forward over the ground, through the wall.
  const RobotModel& robot = Anymal();
  const RobotTerrainCollision checker(robot, LoadNamed("slalom_debris").terrain_mesh);
  const Eigen::Isometry3d base = BaseAt(0.08, 0.0, robot.NominalBaseHeight());
  const Eigen::Vector3d q_swung(0.0, -0.25, -2.3);
  const Eigen::Vector3d foot_W = base * robot.FootPosition(Leg::kLF, q_swung);
  ASSERT_GT(foot_W.x(), 0.542);
  ASSERT_GT(foot_W.z(), 0.05);

  const CollisionReport leg = checker.CheckLeg(Leg::kLF, base, q_swung, false);
  ASSERT_TRUE(leg.collision);
  EXPECT_TRUE(StartsWith(leg.first_shape, "LF_")) << leg.first_shape;
  EXPECT_EQ(leg.obstacle, "terrain");
  // The same leg motion 0.5 m further back, clear of the wall, is free: the wall was hit.
  EXPECT_FALSE(checker.CheckLeg(Leg::kLF, BaseAt(-0.42, 0.0, robot.NominalBaseHeight()), q_swung, false).collision);

  const JointVector& q_ref = robot.ReferenceConfiguration();
  for (Leg other : {Leg::kRF, Leg::kLH, Leg::kRH}) {
    EXPECT_FALSE(checker.CheckLeg(other, base, LegJoints(q_ref, other), true).collision) << LegName(other);
  }
  EXPECT_FALSE(checker.CheckTrunk(base).collision);

  JointVector q = q_ref;
  SetLegJoints(q, Leg::kLF, q_swung);
  const CollisionReport robot_report = checker.CheckRobot(base, q, {false, true, true, true});
  ExpectSameReport(robot_report, leg);
}

// ---- Self-collision -------------------------------------------------------------------------------

TEST(RobotTerrainCollision, CrossedLegsCollideReferenceDoesNot) {
  const RobotTerrainCollision checker(Anymal(), LoadNamed("flat_ground").terrain_mesh);
  const JointVector& q_ref = Anymal().ReferenceConfiguration();
  const CollisionReport reference = checker.CheckSelf(q_ref);
  EXPECT_FALSE(reference.collision) << reference.first_shape << " / " << reference.obstacle;

  // Both front legs abducted towards each other: they cross under the body.
  JointVector crossed = q_ref;
  crossed[0] = -0.5;  // LF_HAA
  crossed[3] = 0.5;   // RF_HAA
  const CollisionReport report = checker.CheckSelf(crossed);
  ASSERT_TRUE(report.collision);
  EXPECT_TRUE(StartsWith(report.first_shape, "LF_")) << report.first_shape;
  EXPECT_TRUE(StartsWith(report.obstacle, "RF_")) << report.obstacle;
  EXPECT_GT(report.penetration, 0.0);
  // Each leg alone is clear.
  JointVector lf_only = q_ref;
  lf_only[0] = -0.5;
  EXPECT_FALSE(checker.CheckSelf(lf_only).collision);
  JointVector rf_only = q_ref;
  rf_only[3] = 0.5;
  EXPECT_FALSE(checker.CheckSelf(rf_only).collision);
}

TEST(RobotTerrainCollision, LegAgainstTrunkCollides) {
  // LF abducted 1 rad inwards: its thigh meets the belly plate.
  const RobotTerrainCollision checker(Anymal(), LoadNamed("flat_ground").terrain_mesh);
  JointVector q = Anymal().ReferenceConfiguration();
  q[0] = -1.0;
  const CollisionReport report = checker.CheckSelf(q);
  ASSERT_TRUE(report.collision);
  EXPECT_TRUE(StartsWith(report.first_shape, "LF_")) << report.first_shape;
  EXPECT_EQ(TrunkShapeNames().count(report.obstacle), 1u) << report.obstacle;
}

TEST(RobotTerrainCollision, SelfCollisionExclusionsAreOwnLegNeighbours) {
  const RobotTerrainCollision checker(Anymal(), LoadNamed("flat_ground").terrain_mesh);
  const auto exclusions = checker.SelfCollisionExclusions();
  const std::set<std::string> trunk = TrunkShapeNames();
  EXPECT_FALSE(exclusions.empty());
  EXPECT_LE(exclusions.size(), 3u * kNumLegs);
  for (const auto& [leg_shape, trunk_shape] : exclusions) {
    EXPECT_EQ(trunk.count(trunk_shape), 1u) << trunk_shape;
    // A leg's thigh next to its own HAA actuator, never another leg's or the main body.
    EXPECT_EQ(leg_shape.substr(0, 3), trunk_shape.substr(0, 3)) << leg_shape << " / " << trunk_shape;
  }
}

// ---- Terrain solid --------------------------------------------------------------------------------

TEST(RobotTerrainCollision, InsideTerrainCountsOverlappingBoxesOnce) {
  // Two overlapping unit cubes: x -0.5..0.5 and 0..1. Parity would call the overlap outside.
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d::Ones());
  TriangleMesh second = MakeBoxMesh(Eigen::Vector3d::Ones());
  second.Transform(Eigen::Isometry3d(Eigen::Translation3d(0.5, 0.0, 0.0)));
  mesh.Append(second);
  const RobotTerrainCollision checker(Anymal(), mesh);
  EXPECT_TRUE(checker.InsideTerrain(Eigen::Vector3d(0.25, 0.1, 0.1)));   // in both
  EXPECT_TRUE(checker.InsideTerrain(Eigen::Vector3d(-0.3, 0.2, -0.2)));  // in the first only
  EXPECT_TRUE(checker.InsideTerrain(Eigen::Vector3d(0.8, -0.3, 0.4)));   // in the second only
  EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(0.25, 0.1, 0.6)));  // above
  EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(0.25, 0.1, -0.6))); // below
  EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(1.2, 0.0, 0.0)));   // beside
  // On the vertical lines through shared triangle edges and corners (diagonals of the faces).
  EXPECT_TRUE(checker.InsideTerrain(Eigen::Vector3d(0.0, 0.0, 0.0)));
  EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(0.0, 0.0, -0.7)));
  EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(0.5, 0.5, -0.7)));
  EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(0.5, 0.5, 0.7)));
  EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(-0.5, -0.5, -0.7)));
}

TEST(RobotTerrainCollision, InsideTerrainOnSharedEdgesCountsEachSurfaceOnce) {
  // A unit cube whose top face is split along x = y and whose bottom face along x = -y: a
  // vertical line through the top diagonal crosses the top on a shared edge but the bottom inside
  // one triangle, so the top must count exactly once.
  TriangleMesh cube = MakeBoxMesh(Eigen::Vector3d::Ones());
  cube.triangles[0] = {0, 2, 1};
  cube.triangles[1] = {1, 2, 3};
  ASSERT_EQ(ValidateMesh(cube), "");
  const RobotTerrainCollision checker(Anymal(), cube);
  for (double t : {-0.3, 0.2, 0.45}) {
    EXPECT_TRUE(checker.InsideTerrain(Eigen::Vector3d(t, t, 0.1))) << t;
    EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(t, t, -0.7))) << t;
    EXPECT_TRUE(checker.InsideTerrain(Eigen::Vector3d(t, -t, -0.1))) << t;
    EXPECT_FALSE(checker.InsideTerrain(Eigen::Vector3d(t, -t, -0.7))) << t;
  }
}

TEST(RobotTerrainCollision, InsideTerrainMatchesTheScenarioBoxes) {
  const Scenario& scenario = LoadNamed("darpa_rubble");
  const RobotTerrainCollision checker(Anymal(), scenario.terrain_mesh);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(-3.0, 3.5), y(-1.0, 1.0), z(-0.6, 0.5);
  int inside_count = 0;
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector3d p(x(rng), y(rng), z(rng));
    bool in_box = false;
    for (const TerrainElement& element : scenario.terrain) {
      const TerrainBox& box = std::get<TerrainBox>(element);
      const Eigen::Vector3d local = RotationFromRpy(box.rpy).transpose() * (p - box.position);
      in_box = in_box || (local.cwiseAbs().array() < 0.5 * box.size.array()).all();
    }
    inside_count += in_box ? 1 : 0;
    ASSERT_EQ(checker.InsideTerrain(p), in_box) << "point " << p.transpose();
  }
  EXPECT_GT(inside_count, 500);
}

// ---- Consistency and determinism ------------------------------------------------------------------

struct RandomQuery {
  Eigen::Isometry3d base;
  JointVector q;
  std::array<bool, kNumLegs> stance;
};

std::vector<RandomQuery> RandomQueries(const Scenario& scenario, int n, unsigned seed) {
  const RobotModel& robot = Anymal();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<RandomQuery> queries;
  while (static_cast<int>(queries.size()) < n) {
    const Eigen::Vector2d xy = scenario.start.position + unit(rng) * (scenario.goal.position - scenario.start.position);
    const auto ground = TerrainHeightAt(scenario.terrain_mesh, xy);
    if (!ground) continue;
    RandomQuery query;
    query.base = Eigen::Isometry3d::Identity();
    query.base.linear() = RotationFromRpy(Eigen::Vector3d(0.2 * unit(rng) - 0.1, 0.3 * unit(rng) - 0.15, unit(rng) - 0.5));
    query.base.translation() << xy, *ground + robot.NominalBaseHeight() + 0.2 * unit(rng) - 0.1;
    for (int j = 0; j < kNumJoints; ++j) {
      query.q[j] = robot.JointLowerBounds()[j] + unit(rng) * (robot.JointUpperBounds()[j] - robot.JointLowerBounds()[j]);
    }
    for (bool& s : query.stance) s = unit(rng) < 0.5;
    queries.push_back(query);
  }
  return queries;
}

TEST(RobotTerrainCollision, WholeRobotIsTrunkThenLegsInOrder) {
  const Scenario& scenario = LoadNamed("darpa_rubble");
  const RobotTerrainCollision checker(Anymal(), scenario.terrain_mesh);
  int collisions = 0;
  for (const RandomQuery& query : RandomQueries(scenario, 400, 3)) {
    CollisionReport expected = checker.CheckTrunk(query.base);
    for (Leg leg : kAllLegs) {
      if (expected.collision) break;
      expected = checker.CheckLeg(leg, query.base, LegJoints(query.q, leg), query.stance[static_cast<std::size_t>(Index(leg))]);
    }
    ExpectSameReport(checker.CheckRobot(query.base, query.q, query.stance), expected);
    collisions += expected.collision ? 1 : 0;
  }
  // The sample holds both outcomes.
  EXPECT_GT(collisions, 40);
  EXPECT_LT(collisions, 360);
}

// An independent reference: every robot primitive against FCL's own bounding-volume hierarchy of
// the whole terrain mesh (no grid, no prefilter), plus the enclosure test of its centre.
std::string FirstHitWithFclBvh(const RobotTerrainCollision& checker, const TriangleMesh& terrain,
                               const Eigen::Isometry3d& base, const JointVector& q) {
  static const TriangleMesh* built_for = nullptr;
  static std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh;
  if (built_for != &terrain) {
    std::vector<fcl::Vector3d> vertices(terrain.vertices.begin(), terrain.vertices.end());
    std::vector<fcl::Triangle> triangles;
    for (const auto& t : terrain.triangles) {
      triangles.emplace_back(static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]), static_cast<std::size_t>(t[2]));
    }
    bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    bvh->beginModel();
    bvh->addSubModel(vertices, triangles);
    bvh->endModel();
    built_for = &terrain;
  }
  const std::vector<Eigen::Isometry3d> links = Anymal().LinkPoses(q);
  for (const CollisionShape& s : Anymal().CollisionShapes()) {
    std::shared_ptr<fcl::CollisionGeometryd> g;
    switch (s.kind) {
      case CollisionShape::Kind::kBox:
        g = std::make_shared<fcl::Boxd>(s.box_size);
        break;
      case CollisionShape::Kind::kCylinder:
        g = std::make_shared<fcl::Cylinderd>(s.radius, s.length);
        break;
      case CollisionShape::Kind::kSphere:
        g = std::make_shared<fcl::Sphered>(s.radius);
        break;
    }
    const Eigen::Isometry3d pose = base * links[static_cast<std::size_t>(s.link_index)] * s.pose_link;
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    if (fcl::collide(g.get(), pose, bvh.get(), Eigen::Isometry3d::Identity(), request, result) > 0 ||
        checker.InsideTerrain(pose.translation())) {
      return s.name;
    }
  }
  return "";
}

TEST(RobotTerrainCollision, AgreesWithFclBvhOverTheWholeMesh) {
  for (const std::string name : {"darpa_rubble", "slalom_debris", "plinth"}) {
    const Scenario& scenario = LoadNamed(name);
    const RobotTerrainCollision checker(Anymal(), scenario.terrain_mesh);
    int collisions = 0;
    for (const RandomQuery& query : RandomQueries(scenario, 300, 17)) {
      const CollisionReport report = checker.CheckRobot(query.base, query.q, kNoStance);
      ASSERT_EQ(report.first_shape, FirstHitWithFclBvh(checker, scenario.terrain_mesh, query.base, query.q))
          << name << " base " << query.base.translation().transpose() << " q " << query.q.transpose();
      collisions += report.collision ? 1 : 0;
    }
    EXPECT_GT(collisions, 30) << name;
    EXPECT_LT(collisions, 270) << name;
  }
}

TEST(RobotTerrainCollision, ResultsAreDeterministic) {
  const Scenario& scenario = LoadNamed("darpa_rubble");
  const RobotTerrainCollision a(Anymal(), scenario.terrain_mesh);
  const RobotTerrainCollision b(Anymal(), scenario.terrain_mesh);
  for (const RandomQuery& query : RandomQueries(scenario, 200, 5)) {
    const CollisionReport first = a.CheckRobot(query.base, query.q, query.stance);
    ExpectSameReport(a.CheckRobot(query.base, query.q, query.stance), first);
    ExpectSameReport(b.CheckRobot(query.base, query.q, query.stance), first);
    ExpectSameReport(a.CheckSelf(query.q), b.CheckSelf(query.q));
  }
}

TEST(RobotTerrainCollision, ConcurrentQueriesMatchSequentialOnes) {
  const Scenario& scenario = LoadNamed("darpa_rubble");
  const RobotTerrainCollision checker(Anymal(), scenario.terrain_mesh);
  const std::vector<RandomQuery> queries = RandomQueries(scenario, 200, 23);
  std::vector<CollisionReport> sequential;
  for (const RandomQuery& query : queries) sequential.push_back(checker.CheckRobot(query.base, query.q, query.stance));
  std::array<std::vector<CollisionReport>, 2> concurrent;
  std::vector<std::thread> threads;
  for (auto& out : concurrent) {
    threads.emplace_back([&checker, &queries, &out] {
      for (const RandomQuery& query : queries) out.push_back(checker.CheckRobot(query.base, query.q, query.stance));
    });
  }
  for (std::thread& t : threads) t.join();
  for (const auto& out : concurrent) {
    ASSERT_EQ(out.size(), sequential.size());
    for (std::size_t i = 0; i < out.size(); ++i) ExpectSameReport(out[i], sequential[i]);
  }
}

TEST(RobotTerrainCollision, PenetrationCanBeLeftUnmeasured) {
  CollisionOptions yes_no;
  yes_no.measure_penetration = false;
  const TriangleMesh& ground = LoadNamed("flat_ground").terrain_mesh;
  const RobotTerrainCollision measured(Anymal(), ground);
  const RobotTerrainCollision unmeasured(Anymal(), ground, yes_no);
  const JointVector& q = Anymal().ReferenceConfiguration();
  const CollisionReport with_depth = measured.CheckRobot(Standing(-0.15), q, kAllStance);
  const CollisionReport without = unmeasured.CheckRobot(Standing(-0.15), q, kAllStance);
  ASSERT_TRUE(with_depth.collision);
  EXPECT_GT(with_depth.penetration, 0.0);
  EXPECT_TRUE(without.collision);
  EXPECT_EQ(without.first_shape, with_depth.first_shape);
  EXPECT_EQ(without.penetration, 0.0);
}

// ---- Input errors -----------------------------------------------------------------------------------

TEST(RobotTerrainCollision, RejectsBadInput) {
  const TriangleMesh& ground = LoadNamed("flat_ground").terrain_mesh;
  EXPECT_THROW(RobotTerrainCollision(Anymal(), TriangleMesh{}), InputError);
  CollisionOptions options;
  options.foot_tolerance = 0.031;  // the foot radius
  EXPECT_THROW(RobotTerrainCollision(Anymal(), ground, options), InputError);
  options.foot_tolerance = -0.001;
  EXPECT_THROW(RobotTerrainCollision(Anymal(), ground, options), InputError);
  options = CollisionOptions{};
  options.adapter_exclusion = 0.4;  // longer than the tube
  EXPECT_THROW(RobotTerrainCollision(Anymal(), ground, options), InputError);
  try {
    options.adapter_exclusion = -0.01;
    RobotTerrainCollision checker(Anymal(), ground, options);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("adapter_exclusion"), std::string::npos) << e.what();
  }
  options = CollisionOptions{};
  options.thigh_margin = 0.1;
  EXPECT_THROW(RobotTerrainCollision(Anymal(), ground, options), InputError);
  options.thigh_margin = -0.001;
  EXPECT_THROW(RobotTerrainCollision(Anymal(), ground, options), InputError);
}

TEST(RobotTerrainCollision, AThighMarginKeepsTerrainFurtherFromTheThighs) {
  // A 1 cm cube swept forward through the LF knee's height at the reference stance: with a
  // 1.5 cm thigh margin it meets the thigh at every place it did without, and at more places.
  std::set<std::string> thigh;
  for (const CollisionShape& c : Anymal().CollisionShapes()) {
    if (c.link == "LF_THIGH") thigh.insert(c.name);
  }
  ASSERT_FALSE(thigh.empty());
  const JointVector q = Anymal().ReferenceConfiguration();
  const Eigen::Isometry3d base = Standing();
  const int knee = Anymal().LinkIndex("LF_SHANK");
  ASSERT_GE(knee, 0);
  const Eigen::Vector3d knee_W = base * Anymal().LinkPoses(q)[static_cast<std::size_t>(knee)].translation();
  CollisionOptions wide;
  wide.thigh_margin = 0.015;
  int hits = 0, wide_hits = 0;
  for (int k = -12; k <= 12; ++k) {
    TerrainBox cube;
    cube.size = Eigen::Vector3d::Constant(0.01);
    cube.position = knee_W + Eigen::Vector3d(0.01 * k, 0.0, 0.0);
    const TriangleMesh terrain = ElementMesh(cube);
    const CollisionReport exact = RobotTerrainCollision(Anymal(), terrain).CheckLeg(Leg::kLF, base, LegJoints(q, Leg::kLF), true);
    const CollisionReport margin =
        RobotTerrainCollision(Anymal(), terrain, wide).CheckLeg(Leg::kLF, base, LegJoints(q, Leg::kLF), true);
    const bool on_thigh = exact.collision && thigh.count(exact.first_shape) > 0;
    const bool on_wide_thigh = margin.collision && thigh.count(margin.first_shape) > 0;
    hits += on_thigh;
    wide_hits += on_wide_thigh;
    if (exact.collision) {
      EXPECT_TRUE(margin.collision) << "cube at " << k << " cm";
    }
  }
  EXPECT_GT(hits, 0);
  EXPECT_GT(wide_hits, hits);
}

}  // namespace
}  // namespace rbcp
