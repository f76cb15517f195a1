#include "rbcp/plan_checker/plan_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <functional>
#include <random>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

using nlohmann::json;

/// A plan with awkward doubles (not representable in few decimal digits, tiny, huge, negative
/// zero) in every field.
ContactPlan AwkwardPlan() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  ContactPlan plan;
  for (int i = 0; i < 5; ++i) {
    WholeBodyState s;
    s.base_position = Eigen::Vector3d(uniform(rng), 1.0 / 3.0 + i, 0.1 + 0.2);
    s.base_rpy = Eigen::Vector3d(-0.0, 1e-300 * (i + 1), std::nextafter(M_PI, 4.0));
    for (int j = 0; j < 12; ++j) s.joints[j] = uniform(rng);
    for (Leg leg : kAllLegs) {
      FootContact& foot = s.feet[static_cast<std::size_t>(Index(leg))];
      foot.position = Eigen::Vector3d(uniform(rng), uniform(rng), 1e20 * uniform(rng));
      foot.normal = Eigen::Vector3d(uniform(rng), uniform(rng), 1.0).normalized();
    }
    s.moving_leg = i == 0 ? -1 : (i - 1) % kNumLegs;
    if (i % 2 == 1) {  // some states carry their swing path
      s.swing_apex_z = 1.0 / 7.0 + i;
      s.swing_bow = Eigen::Vector2d(uniform(rng), -0.0);
    }
    if (i > 0) {  // every step timed
      s.lift_off_s = 0.1 * i + 1.0 / 3.0;
      s.touch_down_s = 0.1 * i + 0.4;
    }
    plan.states.push_back(s);
  }
  return plan;
}

void ExpectBitwiseEqual(const ContactPlan& a, const ContactPlan& b) {
  ASSERT_EQ(a.states.size(), b.states.size());
  const auto same = [](double x, double y) { return std::memcmp(&x, &y, sizeof(double)) == 0; };
  for (std::size_t i = 0; i < a.states.size(); ++i) {
    const WholeBodyState& s = a.states[i];
    const WholeBodyState& t = b.states[i];
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(same(s.base_position[k], t.base_position[k])) << i;
      EXPECT_TRUE(same(s.base_rpy[k], t.base_rpy[k])) << i << " rpy " << k;
      for (std::size_t l = 0; l < 4; ++l) {
        EXPECT_TRUE(same(s.feet[l].position[k], t.feet[l].position[k])) << i;
        EXPECT_TRUE(same(s.feet[l].normal[k], t.feet[l].normal[k])) << i;
      }
    }
    for (int j = 0; j < 12; ++j) EXPECT_TRUE(same(s.joints[j], t.joints[j])) << i;
    EXPECT_EQ(s.moving_leg, t.moving_leg);
    EXPECT_EQ(s.HasSwing(), t.HasSwing()) << i;
    if (s.HasSwing() && t.HasSwing()) {
      EXPECT_TRUE(same(s.swing_apex_z, t.swing_apex_z)) << i;
      EXPECT_TRUE(same(s.swing_bow.x(), t.swing_bow.x()) && same(s.swing_bow.y(), t.swing_bow.y())) << i;
    }
    EXPECT_EQ(s.HasTiming(), t.HasTiming()) << i;
    if (s.HasTiming() && t.HasTiming()) {
      EXPECT_TRUE(same(s.lift_off_s, t.lift_off_s) && same(s.touch_down_s, t.touch_down_s)) << i;
    }
  }
}

TEST(PlanJsonTest, SchemaKeysNameTheJointsInTheirOrder) {
  json document = {{"states", json::array()}};
  AddSchemaKeys(document);
  EXPECT_EQ(document.at("schema_version"), kJsonSchemaVersion);
  const json& names = document.at("joint_names");
  ASSERT_EQ(names.size(), 12u);
  EXPECT_EQ(names[0], "LF_HAA");
  EXPECT_EQ(names[5], "RF_KFE");
  EXPECT_EQ(names[11], "RH_KFE");
  // A document with the keys still reads as a plan.
  EXPECT_TRUE(ContactPlanFromJsonDocument(document).states.empty());
}

TEST(PlanJsonTest, RoundTripIsExactThroughText) {
  const ContactPlan plan = AwkwardPlan();
  const std::string text = ContactPlanToJson(plan).dump();
  ExpectBitwiseEqual(plan, ContactPlanFromJson(json::parse(text)));
  ExpectBitwiseEqual(plan, ContactPlanFromJsonDocument(json::parse(text)));
  ExpectBitwiseEqual(plan, ContactPlanFromJsonDocument(json{{"states", json::parse(text)}, {"steps", 4}}));
}

TEST(PlanJsonTest, Layout) {
  ContactPlan plan;
  WholeBodyState s;
  s.base_position = Eigen::Vector3d(1, 2, 3);
  s.base_rpy = Eigen::Vector3d(0.1, 0.2, 0.3);
  for (int j = 0; j < 12; ++j) s.joints[j] = j;
  s.feet[2].position = Eigen::Vector3d(-1, 0.5, 0);
  plan.states.push_back(s);
  s.moving_leg = Index(Leg::kRH);
  plan.states.push_back(s);
  const json j = ContactPlanToJson(plan);
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["base"]["position"], json({1.0, 2.0, 3.0}));
  EXPECT_EQ(j[0]["base"]["rpy"], json({0.1, 0.2, 0.3}));
  EXPECT_EQ(j[0]["joints"].size(), 12u);
  EXPECT_EQ(j[0]["joints"][11], 11.0);
  EXPECT_EQ(j[0]["feet"].size(), 4u);
  EXPECT_EQ(j[0]["feet"][0]["leg"], "LF");
  EXPECT_EQ(j[0]["feet"][3]["leg"], "RH");
  EXPECT_EQ(j[0]["feet"][2]["leg"], "LH");
  EXPECT_EQ(j[0]["feet"][2]["position"], json({-1.0, 0.5, 0.0}));
  EXPECT_EQ(j[0]["feet"][2]["normal"], json({0.0, 0.0, 1.0}));
  EXPECT_TRUE(j[0]["moving_leg"].is_null());
  EXPECT_EQ(j[1]["moving_leg"], "RH");
  EXPECT_EQ(j[0].size(), 4u);  // base, joints, feet, moving_leg and nothing else
}

TEST(PlanJsonTest, FeetInAnyOrder) {
  const ContactPlan plan = AwkwardPlan();
  json j = ContactPlanToJson(plan);
  std::swap(j[1]["feet"][0], j[1]["feet"][3]);
  std::swap(j[1]["feet"][1], j[1]["feet"][2]);
  ExpectBitwiseEqual(plan, ContactPlanFromJson(j));
}

TEST(PlanJsonTest, IntegersAreNumbers) {
  json j = ContactPlanToJson(AwkwardPlan());
  j[2]["joints"][0] = 1;
  EXPECT_EQ(ContactPlanFromJson(j).states[2].joints[0], 1.0);
}

TEST(PlanJsonTest, InvalidMovingLegIsNotWritten) {
  ContactPlan plan = AwkwardPlan();
  plan.states[3].moving_leg = 4;
  EXPECT_THROW(ContactPlanToJson(plan), InputError);
}

/// The message of the InputError that reading `j` throws ("" when it does not throw).
std::string ReadError(const json& j, bool document = false) {
  try {
    if (document) {
      ContactPlanFromJsonDocument(j);
    } else {
      ContactPlanFromJson(j);
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

struct Corruption {
  const char* name;
  std::function<void(json&)> apply;
  const char* message;  ///< expected substring of the error
};

class PlanJsonStrictTest : public ::testing::TestWithParam<Corruption> {};

TEST_P(PlanJsonStrictTest, Rejects) {
  json j = ContactPlanToJson(AwkwardPlan());
  GetParam().apply(j);
  const std::string error = ReadError(j);
  EXPECT_NE(error.find(GetParam().message), std::string::npos) << "got: " << error;
}

INSTANTIATE_TEST_SUITE_P(
    Corruptions, PlanJsonStrictTest,
    ::testing::Values(
        Corruption{"missing_joints", [](json& j) { j[2].erase("joints"); },
                   "state 2: expected a key 'joints', got an object without it"},
        Corruption{"unknown_key", [](json& j) { j[1]["velocity"] = 0; },
                   "state 1: expected only the keys base, joints, feet, moving_leg, swing (optional), timing (optional), got an unknown key 'velocity'"},
        Corruption{"short_joints", [](json& j) { j[3]["joints"].erase(0); },
                   "state 3: 'joints': expected an array of 12 numbers, got an array of 11 elements"},
        Corruption{"string_joint", [](json& j) { j[3]["joints"][4] = "0.5"; },
                   "state 3: 'joints'[4]: expected a number, got a string (\"0.5\")"},
        Corruption{"base_not_object", [](json& j) { j[0]["base"] = json::array(); },
                   "state 0: 'base': expected an object, got an array of 0 elements"},
        Corruption{"base_missing_rpy", [](json& j) { j[0]["base"].erase("rpy"); },
                   "state 0: 'base': expected a key 'rpy', got an object without it"},
        Corruption{"position_2d", [](json& j) { j[4]["base"]["position"].erase(2); },
                   "state 4: 'base'.'position': expected an array of 3 numbers, got an array of 2 elements"},
        Corruption{"three_feet", [](json& j) { j[1]["feet"].erase(3); },
                   "state 1: 'feet': expected an array of 4 feet, got an array of 3 elements"},
        Corruption{"bad_leg_name", [](json& j) { j[1]["feet"][2]["leg"] = "XX"; },
                   "state 1: 'feet'[2].'leg': expected one of \"LF\", \"RF\", \"LH\", \"RH\", got a string (\"XX\")"},
        Corruption{"duplicate_leg", [](json& j) { j[1]["feet"][2]["leg"] = "LF"; },
                   "state 1: 'feet'[2].'leg': expected each of LF, RF, LH, RH once, got a string (\"LF\")"},
        Corruption{"foot_extra_key", [](json& j) { j[1]["feet"][0]["force"] = 1; },
                   "state 1: 'feet'[0]: expected only the keys leg, position, normal, got an unknown key 'force'"},
        Corruption{"normal_null", [](json& j) { j[2]["feet"][1]["normal"] = nullptr; },
                   "state 2: 'feet'[1].'normal': expected an array of 3 numbers, got null"},
        Corruption{"moving_leg_number", [](json& j) { j[2]["moving_leg"] = 1; },
                   "state 2: 'moving_leg': expected one of \"LF\", \"RF\", \"LH\", \"RH\", got a number (1)"},
        Corruption{"moving_leg_missing", [](json& j) { j[2].erase("moving_leg"); },
                   "state 2: expected a key 'moving_leg', got an object without it"},
        Corruption{"state_not_object", [](json& j) { j[1] = true; },
                   "state 1: expected an object, got a boolean (true)"},
        Corruption{"timing_missing_key", [](json& j) { j[2]["timing"].erase("touch_down_s"); },
                   "state 2: 'timing': expected a key 'touch_down_s', got an object without it"},
        Corruption{"timing_nan", [](json& j) { j[2]["timing"]["lift_off_s"] = "nan"; },
                   "state 2: 'timing'.'lift_off_s': expected a finite number"},
        Corruption{"timing_backwards", [](json& j) { j[3]["timing"]["lift_off_s"] = 0.0; },
                   "contact plan: timing: state 3: expected lift-off at or after 0.600 s"},
        Corruption{"timing_partial", [](json& j) { j[4].erase("timing"); },
                   "contact plan: timing: some steps are timed and others not"},
        Corruption{"overflow", [](json& j) { j[0]["joints"][0] = std::numeric_limits<double>::infinity(); },
                   "state 0: 'joints'[0]: expected a finite number"}),
    [](const ::testing::TestParamInfo<Corruption>& info) { return std::string(info.param.name); });

TEST(PlanJsonTest, DocumentForms) {
  EXPECT_NE(ReadError(json::object({{"steps", 3}}), true)
                .find("expected an array of states or an object with a key 'states', got an object without 'states'"),
            std::string::npos);
  EXPECT_NE(ReadError(json{{"states", nullptr}}, true)
                .find("'states': expected an array of states, got null"),
            std::string::npos);
  EXPECT_NE(ReadError(json("plan"), true).find("got a string (\"plan\")"), std::string::npos);
  EXPECT_NE(ReadError(json::object()).find("contact plan: expected an array of states, got an object"),
            std::string::npos);
  EXPECT_TRUE(ContactPlanFromJsonDocument(json::array()).states.empty());
}

}  // namespace
}  // namespace rbcp
