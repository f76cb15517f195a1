#include "rbcp/root_planner/reachability_checker.h"

#include <gtest/gtest.h>

#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/rom.h"
#include "rbcp/root_planner/trunk_shape.h"
#include "test_terrains.h"

namespace rbcp {
namespace {

using test::Box;
using test::MakePlatforms;
using test::Rectangle;

class ReachabilityTest : public ::testing::Test {
 protected:
  ReachabilityTest()
      : robot_(RobotModel::LoadDefault(test::kConfigDir)),
        roms_(LoadRoms(test::kConfigDir + "/robots/anymal_b_roms")),
        trunk_(MakeTrunkShape(TrunkShapeConfig{})) {}

  ReachabilityChecker Make(const test::Platforms& p) { return ReachabilityChecker(p.terrain, p.surfaces, roms_, trunk_); }
  double Height() const { return robot_.NominalBaseHeight(); }

  RobotModel robot_;
  std::array<ConvexPolytope, kNumLegs> roms_;
  ConvexPolytope trunk_;
};

TEST_F(ReachabilityTest, StandingOnFlatGroundIsValid) {
  auto checker = Make(MakePlatforms({{-3.0, 3.0}}));
  for (double yaw : {0.0, 0.8, -2.5, M_PI}) {
    const ReachabilityReport report = checker.Check({0.2, -0.3, Height()}, yaw);
    EXPECT_TRUE(report.Valid()) << report.Reason();
    EXPECT_TRUE(report.Reason().empty());
    EXPECT_TRUE(checker.IsValid({0.2, -0.3, Height()}, yaw));
  }
  // Crouched a little, raised a little: still valid.
  EXPECT_TRUE(checker.IsValid({0.0, 0.0, Height() - 0.05}, 0.0));
  EXPECT_TRUE(checker.IsValid({0.0, 0.0, Height() + 0.05}, 0.0));
}

TEST_F(ReachabilityTest, AKilometreFloorOfTwoTrianglesTakesLittleMemory) {
  // The grids' cells grow with the terrain so that their size follows the triangle count, not
  // the area: with 0.1 m cells this floor alone would list 10^8 cells.
  TriangleMesh floor;
  floor.vertices = {{-500, -500, 0}, {500, -500, 0}, {500, 500, 0}, {-500, 500, 0}};
  floor.triangles = {{0, 1, 2}, {0, 2, 3}};
  AffordanceSurface surface;
  surface.vertices = floor.vertices;
  surface.normal = Eigen::Vector3d::UnitZ();
  surface.area = 1e6;
  ReachabilityChecker checker(floor, {surface}, roms_, trunk_);
  EXPECT_TRUE(checker.IsValid({120.0, -40.0, Height()}, 0.3));
  const ReachabilityReport low = checker.Check({120.0, -40.0, 0.3}, 0.0);
  EXPECT_TRUE(low.trunk_collision) << "the coarser grid still finds the floor";
  EXPECT_FALSE(checker.IsValid({120.0, -40.0, -0.5}, 0.0)) << "below the floor";
}

TEST_F(ReachabilityTest, TooHighOrTooLowIsInvalid) {
  auto checker = Make(MakePlatforms({{-3.0, 3.0}}));
  const ReachabilityReport high = checker.Check({0.0, 0.0, 1.0}, 0.0);
  EXPECT_FALSE(high.Valid());
  EXPECT_FALSE(high.trunk_collision);
  EXPECT_EQ(high.Reason(), "no contact surface in reach of LF, RF, LH, RH");
  // The keel bottom is 0.325 m below the base: lower than that, the trunk hits the ground.
  const ReachabilityReport low = checker.Check({0.0, 0.0, 0.3}, 0.0);
  EXPECT_TRUE(low.trunk_collision);
  EXPECT_FALSE(low.Valid());
  EXPECT_NE(low.Reason().find("trunk collides"), std::string::npos);
}

TEST_F(ReachabilityTest, GapWiderThanTheLegsReachIsInvalid) {
  // 1.8 m gap centred under the base: neither fore nor hind legs reach across.
  auto wide = Make(MakePlatforms({{-3.0, -0.9}, {0.9, 3.0}}));
  const ReachabilityReport report = wide.Check({0.0, 0.0, Height()}, 0.0);
  EXPECT_FALSE(report.Valid());
  EXPECT_FALSE(report.trunk_collision);
  for (Leg leg : kAllLegs) EXPECT_FALSE(report.LegInReach(leg)) << LegName(leg);
  // Turned by 90 deg the legs reach along y, where there is no ground either.
  EXPECT_FALSE(wide.IsValid({0.0, 0.0, Height()}, M_PI / 2.0));
  // A 0.3 m gap is stepped over.
  auto narrow = Make(MakePlatforms({{-3.0, -0.15}, {0.15, 3.0}}));
  EXPECT_TRUE(narrow.IsValid({0.0, 0.0, Height()}, 0.0));
}

TEST_F(ReachabilityTest, ReportsWhichLegsLackASurface) {
  // Ground only behind x = 0: with the base at x = 0.5 the fore legs hang over the edge.
  auto checker = Make(MakePlatforms({{-3.0, 0.0}}));
  const ReachabilityReport report = checker.Check({0.5, 0.0, Height()}, 0.0);
  EXPECT_FALSE(report.trunk_collision);
  EXPECT_FALSE(report.LegInReach(Leg::kLF));
  EXPECT_FALSE(report.LegInReach(Leg::kRF));
  EXPECT_TRUE(report.LegInReach(Leg::kLH));
  EXPECT_TRUE(report.LegInReach(Leg::kRH));
  EXPECT_EQ(report.Reason(), "no contact surface in reach of LF, RF");
  // Facing backwards, the hind legs are the ones over the edge... and the fore legs reach back.
  const ReachabilityReport turned = checker.Check({0.5, 0.0, Height()}, M_PI);
  EXPECT_TRUE(turned.LegInReach(Leg::kLF));
  EXPECT_FALSE(turned.LegInReach(Leg::kLH));
}

TEST_F(ReachabilityTest, TrunkInsideAnObstacleIsInvalid) {
  test::Platforms p = MakePlatforms({{-3.0, 3.0}});
  // A 1.2 m cube on the floor, larger than the trunk in every direction.
  p.terrain.Append(Box({-0.6, -0.6, 0.0}, {0.6, 0.6, 1.2}));
  auto checker = Make(p);
  const ReachabilityReport inside = checker.Check({0.0, 0.0, 0.6}, 0.0);
  EXPECT_TRUE(inside.trunk_collision);
  EXPECT_FALSE(inside.Valid());
  EXPECT_TRUE(checker.TrunkCollides({0.0, 0.0, 0.6}, 0.3));
  // Overlapping the cube's side, and clear of it.
  EXPECT_TRUE(checker.TrunkCollides({0.8, 0.0, Height()}, 0.0));
  EXPECT_FALSE(checker.TrunkCollides({1.0, 0.0, Height()}, 0.0));
  EXPECT_TRUE(checker.IsValid({1.0, 0.0, Height()}, 0.0));
  // The keel passes over a low obstacle, the box front over a higher step but not the keel.
  test::Platforms low = MakePlatforms({{-3.0, 3.0}});
  low.terrain.Append(Box({-0.2, -0.5, 0.0}, {0.2, 0.5, 0.10}));
  EXPECT_FALSE(Make(low).TrunkCollides({0.0, 0.0, Height()}, 0.0));
  test::Platforms high = MakePlatforms({{-3.0, 3.0}});
  high.terrain.Append(Box({-0.02, -0.5, 0.0}, {0.02, 0.5, 0.2}));
  EXPECT_TRUE(Make(high).TrunkCollides({0.0, 0.0, Height()}, 0.0));
  high.terrain.Append(Box({0.98, -0.5, 0.0}, {1.02, 0.5, 0.2}));
  EXPECT_FALSE(Make(high).TrunkCollides({0.72, 0.0, Height()}, 0.0));
}

TEST_F(ReachabilityTest, SurfacesAreSeparateFromTheTerrain) {
  // Terrain everywhere but a surface only far away: the legs find nothing.
  test::Platforms p = MakePlatforms({{-3.0, 3.0}});
  p.surfaces = {Rectangle(2.0, 3.0, -1.0, 1.0, 0.0)};
  auto checker = Make(p);
  EXPECT_EQ(checker.NumSurfaces(), 1u);
  EXPECT_FALSE(checker.IsValid({0.0, 0.0, Height()}, 0.0));
  EXPECT_TRUE(checker.IsValid({2.5, 0.0, Height()}, 0.0));
  EXPECT_EQ(checker.Queries(), 2);
}

TEST_F(ReachabilityTest, RejectsBadInput) {
  test::Platforms p = MakePlatforms({{-3.0, 3.0}});
  EXPECT_THROW(ReachabilityChecker(TriangleMesh{}, p.surfaces, roms_, trunk_), InputError);
  AffordanceSurface degenerate = Rectangle(0, 1, 0, 1, 0);
  degenerate.vertices.resize(2);
  EXPECT_THROW(ReachabilityChecker(p.terrain, {degenerate}, roms_, trunk_), InputError);
}

}  // namespace
}  // namespace rbcp
