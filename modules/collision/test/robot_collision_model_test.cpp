#include "rbcp/collision/robot_collision_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <utility>

#include "fcl_shape.h"
#include "rbcp/collision/robot_self_collision.h"
#include "rbcp/core/error.h"

namespace rbcp {
namespace {

const std::string kConfigDir = std::string(RBCP_SOURCE_DIR) + "/config";

const RobotModel& Anymal() {
  static const RobotModel model = RobotModel::LoadDefault(kConfigDir);
  return model;
}

const RobotCollisionModel& Model() {
  static const RobotCollisionModel model(Anymal());
  return model;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

using NamePairs = std::set<std::pair<std::string, std::string>>;

NamePairs Names(const RobotCollisionModel& model, const std::vector<PrimitivePair>& pairs) {
  NamePairs names;
  for (const PrimitivePair& p : pairs) {
    names.emplace(model.Primitives()[static_cast<std::size_t>(p.a)].name, model.Primitives()[static_cast<std::size_t>(p.b)].name);
  }
  return names;
}

// The primitives of `leg` (or of the trunk, when leg is nullopt) on `body`.
std::vector<int> On(const RobotCollisionModel& model, std::optional<Leg> leg, RobotBody body) {
  std::vector<int> out;
  for (std::size_t i = 0; i < model.Primitives().size(); ++i) {
    const CollisionPrimitive& p = model.Primitives()[i];
    if (p.leg == leg && p.body == body) out.push_back(static_cast<int>(i));
  }
  return out;
}

TEST(RobotCollisionModel, EachPrimitiveRidesOnTheBodyItsLegsJointsMove) {
  const auto& links = Anymal().Links();
  ASSERT_EQ(Model().Primitives().size(), Anymal().CollisionShapes().size());
  for (std::size_t i = 0; i < Model().Primitives().size(); ++i) {
    const CollisionPrimitive& p = Model().Primitives()[i];
    const std::string& link = links[static_cast<std::size_t>(p.link_index)].name;
    EXPECT_EQ(p.name, Anymal().CollisionShapes()[i].name);
    RobotBody expected = RobotBody::kShank;  // the SHANK, ADAPTER and FOOT links
    if (link == "base") expected = RobotBody::kTrunk;
    if (EndsWith(link, "_HIP")) expected = RobotBody::kHip;
    if (EndsWith(link, "_THIGH")) expected = RobotBody::kThigh;
    EXPECT_EQ(p.body, expected) << p.name << " on " << link;
    EXPECT_EQ(p.leg.has_value(), expected != RobotBody::kTrunk) << p.name;
  }
  // The lists partition the primitives: the trunk's, then each leg's from hip to foot.
  std::vector<int> all = Model().Trunk();
  for (Leg leg : kAllLegs) {
    const std::vector<int>& list = Model().LegPrimitives(leg);
    EXPECT_TRUE(std::is_sorted(list.begin(), list.end()));
    EXPECT_EQ(Model().Primitives()[static_cast<std::size_t>(list.front())].body, RobotBody::kHip) << LegName(leg);
    EXPECT_TRUE(EndsWith(Model().Primitives()[static_cast<std::size_t>(list.back())].name, "_foot")) << LegName(leg);
    all.insert(all.end(), list.begin(), list.end());
  }
  ASSERT_EQ(all.size(), Model().Primitives().size());
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(all[i], static_cast<int>(i));
}

TEST(RobotCollisionModel, LegTrunkPairsLeaveOutTheHipAndTheOverlapsByConstruction) {
  const std::vector<int>& trunk = Model().Trunk();
  NamePairs overlaps;
  for (Leg leg : kAllLegs) {
    // Thigh and shank against the trunk, each pair either tested or an overlap by construction.
    NamePairs expected;
    for (RobotBody body : {RobotBody::kThigh, RobotBody::kShank}) {
      for (int a : On(Model(), leg, body)) {
        for (int b : trunk) expected.merge(Names(Model(), {{a, b}}));
      }
    }
    const NamePairs tested = Names(Model(), Model().LegTrunkPairs(leg));
    NamePairs both = tested;
    for (const auto& [a, b] : Names(Model(), Model().ReferenceOverlaps())) {
      if (a.rfind(std::string(LegName(leg)), 0) == 0) {
        EXPECT_EQ(tested.count({a, b}), 0u) << a << " / " << b;
        both.emplace(a, b);
      }
    }
    EXPECT_EQ(both, expected) << LegName(leg);
  }
  // The overlaps by construction: each thigh around its own HAA actuator.
  for (Leg leg : kAllLegs) {
    const std::string l(LegName(leg));
    overlaps.emplace(l + "_thigh_with_heat_fins", l + "_HAA_actuator");
    overlaps.emplace(l + "_upper_protector", l + "_HAA_actuator");
  }
  EXPECT_EQ(Names(Model(), Model().ReferenceOverlaps()), overlaps);
}

TEST(RobotCollisionModel, LegLegPairsHoldEveryPrimitiveOfBothLegs) {
  for (Leg a : kAllLegs) {
    for (Leg b : kAllLegs) {
      if (Index(a) >= Index(b)) {
        EXPECT_THROW(Model().LegLegPairs(a, b), InvariantError);
        continue;
      }
      const auto& pairs = Model().LegLegPairs(a, b);
      ASSERT_EQ(pairs.size(), Model().LegPrimitives(a).size() * Model().LegPrimitives(b).size());
      for (const PrimitivePair& p : pairs) {
        EXPECT_EQ(Model().Primitives()[static_cast<std::size_t>(p.a)].leg, a);
        EXPECT_EQ(Model().Primitives()[static_cast<std::size_t>(p.b)].leg, b);
      }
    }
  }
}

TEST(RobotCollisionModel, ShankHipPairsAreTheShankAgainstItsOwnHip) {
  for (Leg leg : kAllLegs) {
    NamePairs expected;
    for (int a : On(Model(), leg, RobotBody::kShank)) {
      for (int h : On(Model(), leg, RobotBody::kHip)) expected.merge(Names(Model(), {{a, h}}));
    }
    EXPECT_FALSE(expected.empty());
    EXPECT_EQ(Names(Model(), Model().ShankHipPairs(leg)), expected) << LegName(leg);
  }
}

TEST(RobotCollisionModel, TheShankDoesNotReachItsHipWithinTheJointBounds) {
  // Why the whole-robot tests may leave ShankHipPairs out: the shank's pose relative to its hip
  // depends on HFE and KFE only; a fine grid over their planning bounds never brings them together.
  using collision_detail::FclShape;
  std::vector<FclShape> shapes;
  for (const CollisionPrimitive& p : Model().Primitives()) shapes.emplace_back(p);
  fcl::CollisionResultd result;
  std::vector<Eigen::Isometry3d> links;
  constexpr int kSteps = 60;
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d lo = Anymal().LegLowerBounds(leg), hi = Anymal().LegUpperBounds(leg);
    for (int i = 0; i <= kSteps; ++i) {
      for (int k = 0; k <= kSteps; ++k) {
        const Eigen::Vector3d q_leg(0.0, lo.y() + (hi.y() - lo.y()) * i / kSteps, lo.z() + (hi.z() - lo.z()) * k / kSteps);
        JointVector q = Anymal().ReferenceConfiguration();
        SetLegJoints(q, leg, q_leg);
        Anymal().LinkPoses(q, &links);
        for (const PrimitivePair& p : Model().ShankHipPairs(leg)) {
          const FclShape& a = shapes[static_cast<std::size_t>(p.a)];
          const FclShape& b = shapes[static_cast<std::size_t>(p.b)];
          const Eigen::Isometry3d Ta = links[static_cast<std::size_t>(a.link_index)] * a.pose_link;
          const Eigen::Isometry3d Tb = links[static_cast<std::size_t>(b.link_index)] * b.pose_link;
          EXPECT_FALSE(collision_detail::ShapesTouch(a, Ta, a.Bounds(Ta), b, Tb, b.Bounds(Tb), result))
              << a.name << " / " << b.name << " at HFE " << q_leg.y() << ", KFE " << q_leg.z();
        }
      }
    }
  }
}

TEST(RobotCollisionModel, MarginsGrowTheThighsAndTheTrunkAndWhatTheyOverlap) {
  const RobotCollisionModel grown(Anymal(), CollisionMargins{0.02, 0.01});
  ASSERT_EQ(grown.Primitives().size(), Model().Primitives().size());
  for (std::size_t i = 0; i < grown.Primitives().size(); ++i) {
    const CollisionPrimitive& g = grown.Primitives()[i];
    const CollisionPrimitive& e = Model().Primitives()[i];
    const double margin = g.body == RobotBody::kThigh ? 0.02 : (g.body == RobotBody::kTrunk ? 0.01 : 0.0);
    EXPECT_DOUBLE_EQ(g.radius, e.radius + margin) << g.name;
    EXPECT_DOUBLE_EQ(g.half_length, e.half_length + margin) << g.name;
    EXPECT_TRUE(g.half_extents.isApprox(e.half_extents + Eigen::Vector3d::Constant(margin))) << g.name;
  }
  const NamePairs exact = Names(Model(), Model().ReferenceOverlaps());
  const NamePairs wider = Names(grown, grown.ReferenceOverlaps());
  EXPECT_GT(wider.size(), exact.size());
  EXPECT_TRUE(std::includes(wider.begin(), wider.end(), exact.begin(), exact.end()));
  // Decided on the grown primitives, the pairs keep the reference configuration free.
  const RobotSelfCollision self(Anymal(), grown);
  EXPECT_FALSE(self.Check(Anymal().ReferenceConfiguration()).collision);
  EXPECT_THROW(RobotCollisionModel(Anymal(), CollisionMargins{-0.01, 0.0}), InvariantError);
}

TEST(RobotSelfCollision, LegTrunkCheckLeavesTheOtherLegsOut) {
  const RobotSelfCollision self(Anymal());
  const JointVector& q_ref = Anymal().ReferenceConfiguration();
  EXPECT_FALSE(self.Check(q_ref).collision);
  // Both front legs abducted towards each other: they cross under the body, clear of the trunk.
  JointVector crossed = q_ref;
  crossed[0] = -0.5;  // LF_HAA
  crossed[3] = 0.5;   // RF_HAA
  const CollisionReport legs = self.Check(crossed);
  ASSERT_TRUE(legs.collision);
  EXPECT_EQ(legs.first_shape.substr(0, 3), "LF_");
  EXPECT_EQ(legs.obstacle.substr(0, 3), "RF_");
  EXPECT_TRUE(self.Check(crossed, Leg::kLF).collision);
  EXPECT_FALSE(self.CheckLegTrunk(crossed, Leg::kLF).collision);
  EXPECT_FALSE(self.CheckLegTrunk(crossed, Leg::kRF).collision);
  // LF abducted 1 rad inwards: its thigh meets the belly plate.
  JointVector inward = q_ref;
  inward[0] = -1.0;
  const CollisionReport trunk = self.CheckLegTrunk(inward, Leg::kLF);
  ASSERT_TRUE(trunk.collision);
  EXPECT_EQ(trunk.first_shape.substr(0, 3), "LF_");
  const auto& trunk_list = Model().Trunk();
  EXPECT_TRUE(std::any_of(trunk_list.begin(), trunk_list.end(), [&](int i) {
    return Model().Primitives()[static_cast<std::size_t>(i)].name == trunk.obstacle;
  })) << trunk.obstacle;
  EXPECT_FALSE(self.CheckLegTrunk(inward, Leg::kRF).collision);
}

}  // namespace
}  // namespace rbcp
