#include "leg_self_collision.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "limb_database_test_util.h"

namespace rbcp::limb_database_detail {
namespace {

using test::Anymal;

/// An LF joint triple mirrored onto `leg` (right legs negate HAA, hind legs negate HFE and KFE).
Eigen::Vector3d Mirrored(const Eigen::Vector3d& q_lf, Leg leg) {
  return Eigen::Vector3d(LeftSign(leg) * q_lf[0], ForeSign(leg) * q_lf[1], ForeSign(leg) * q_lf[2]);
}

/// A shape name with the leg prefix ("RH_shank") replaced by "XX".
std::string Generic(const std::string& name) {
  return name.size() > 3 && name[2] == '_' && LegFromName(name.substr(0, 2)) ? "XX" + name.substr(2) : name;
}

bool Contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(LegSelfCollision, ReferenceStanceIsFree) {
  for (Leg leg : kAllLegs) {
    const LegSelfCollision filter(Anymal(), leg);
    EXPECT_FALSE(filter.InCollision(LegJoints(Anymal().ReferenceConfiguration(), leg))) << LegName(leg);
  }
}

TEST(LegSelfCollision, ChecksShankAndFootAgainstTrunkAndHipAndThighAgainstTrunk) {
  const LegSelfCollision filter(Anymal(), Leg::kLF);
  const std::vector<std::string> pairs = filter.PairNames();
  EXPECT_TRUE(Contains(pairs, "LF_foot / main_body"));
  EXPECT_TRUE(Contains(pairs, "LF_shank / main_body"));
  EXPECT_TRUE(Contains(pairs, "LF_adapter_tube / belly_plate_middle_bump"));
  EXPECT_TRUE(Contains(pairs, "LF_foot / RF_HAA_actuator"));
  EXPECT_TRUE(Contains(pairs, "LF_shank / LF_protector"));
  EXPECT_TRUE(Contains(pairs, "LF_foot / LF_heatfins"));
  EXPECT_TRUE(Contains(pairs, "LF_thigh_with_heat_fins / main_body"));
  EXPECT_TRUE(Contains(pairs, "LF_KFE_actuator / belly_plate_front_bump"));
  // Parts joined at a joint are never tested against each other.
  EXPECT_FALSE(Contains(pairs, "LF_shank / LF_KFE_actuator"));
  EXPECT_FALSE(Contains(pairs, "LF_thigh_with_heat_fins / LF_protector"));
  // The thigh's upper protector meets its own HAA actuator by construction.
  EXPECT_FALSE(Contains(pairs, "LF_upper_protector / LF_HAA_actuator"));
  // No pair involves another leg's moving parts.
  for (const std::string& p : pairs) EXPECT_EQ(p.find("RF_shank"), std::string::npos) << p;
}

TEST(LegSelfCollision, PairsAreTheCollisionModelsLegTrunkAndShankHipPairs) {
  const RobotCollisionModel model(Anymal());
  const auto name = [&](int i) { return model.Primitives()[static_cast<std::size_t>(i)].name; };
  for (Leg leg : kAllLegs) {
    std::vector<std::string> expected;
    for (const auto* pairs : {&model.LegTrunkPairs(leg), &model.ShankHipPairs(leg)}) {
      for (const PrimitivePair& p : *pairs) expected.push_back(name(p.a) + " / " + name(p.b));
    }
    std::vector<std::string> tested = LegSelfCollision(Anymal(), leg).PairNames();
    std::sort(expected.begin(), expected.end());
    std::sort(tested.begin(), tested.end());
    EXPECT_EQ(tested, expected) << LegName(leg);
  }
}

TEST(LegSelfCollision, KnownCollisionsOnEveryLeg) {
  struct Case {
    Eigen::Vector3d q_lf;
    std::string first, second;
  };
  const std::vector<Case> cases = {
      // Thigh swung back and up, hip turned outward: the knee folds over the trunk.
      {{0.9, 2.3, -1.0}, "XX_shank", "main_body"},
      // Hip turned inward: the thigh reaches under the belly.
      {{-1.0, 0.6, -1.2}, "XX_thigh_with_heat_fins", "belly_plate_XX_bump"},
  };
  for (Leg leg : kAllLegs) {
    const LegSelfCollision filter(Anymal(), leg);
    for (const Case& c : cases) {
      const auto hit = filter.FirstCollision(Mirrored(c.q_lf, leg));
      const std::string bump = ForeSign(leg) > 0 ? "belly_plate_front_bump" : "belly_plate_hind_bump";
      const std::string second = c.second == "belly_plate_XX_bump" ? bump : c.second;
      EXPECT_EQ(Generic(hit.first), c.first) << LegName(leg);
      EXPECT_EQ(hit.second, second) << LegName(leg);
    }
    // Foot under the belly, yet clear of it.
    EXPECT_FALSE(filter.InCollision(Mirrored({-0.9, 0.3, -0.5}, leg))) << LegName(leg);
    // Knee folded with the foot raised to hip height in front of the hip.
    EXPECT_FALSE(filter.InCollision(Mirrored({0.3, 0.5, -2.3}, leg))) << LegName(leg);
  }
}

TEST(LegSelfCollision, MirroredLegsAgree) {
  // The robot is left/right and fore/hind symmetric, so mirrored configurations collide alike.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> haa(-1.0, 1.0), hfe(-0.25, 2.35), kfe(-2.35, 0.0);
  std::array<LegSelfCollision, 4> filters = {LegSelfCollision(Anymal(), Leg::kLF), LegSelfCollision(Anymal(), Leg::kRF),
                                             LegSelfCollision(Anymal(), Leg::kLH), LegSelfCollision(Anymal(), Leg::kRH)};
  int collisions = 0;
  int disagreements = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d q(haa(rng), hfe(rng), kfe(rng));
    const bool lf = filters[0].InCollision(q);
    collisions += lf ? 1 : 0;
    for (Leg leg : {Leg::kRF, Leg::kLH, Leg::kRH}) {
      disagreements += filters[static_cast<std::size_t>(Index(leg))].InCollision(Mirrored(q, leg)) != lf ? 1 : 0;
    }
  }
  EXPECT_GT(collisions, n / 20);
  EXPECT_LT(collisions, n / 2);
  // The URDF rounds pi/2 to 1.5708, so a configuration grazing a surface may differ.
  EXPECT_LE(disagreements, 3);
}

}  // namespace
}  // namespace rbcp::limb_database_detail
