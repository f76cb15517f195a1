#include "rbcp/transport/convert.h"

#include <gtest/gtest.h>

#include <limits>

#include "rbcp/core/error.h"

namespace rbcp::transport {
namespace {

TEST(Convert, TerrainRoundTrip) {
  TriangleMesh box = MakeBoxMesh({1.0, 2.0, 0.5});
  const auto msg = ToTerrainMsg(box, 42, "box");
  EXPECT_EQ(msg.utime, 42);
  EXPECT_EQ(msg.scenario_name, "box");
  EXPECT_EQ(msg.num_triangles, 12);
  const TriangleMesh back = FromTerrainMsg(msg);
  ASSERT_EQ(back.vertices.size(), box.vertices.size());
  for (std::size_t i = 0; i < box.vertices.size(); ++i) EXPECT_EQ(back.vertices[i], box.vertices[i]);
  EXPECT_EQ(back.triangles, box.triangles);
}

TEST(Convert, MalformedTerrainIsRejectedWithAReason) {
  auto msg = ToTerrainMsg(MakeBoxMesh({1, 1, 1}), 0, "");
  auto bad = msg;
  bad.num_triangles = 13;
  EXPECT_THROW(FromTerrainMsg(bad), InputError);
  bad = msg;
  bad.vertices[2][1] = std::numeric_limits<double>::quiet_NaN();
  try {
    FromTerrainMsg(bad);
    FAIL() << "NaN accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "terrain mesh: vertex 2 is not finite");
  }
  bad = msg;
  bad.triangles[0][0] = 100;
  EXPECT_THROW(FromTerrainMsg(bad), InputError);
  bad = msg;
  bad.num_triangles = 0;
  bad.triangles.clear();
  EXPECT_THROW(FromTerrainMsg(bad), InputError);
}

TEST(Convert, AffordanceRoundTripAndValidation) {
  AffordanceSurface s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  s.normal = {0, 0, 1};
  s.area = 0.5;
  const auto msg = ToAffordanceMsg({s, s}, 7);
  EXPECT_EQ(msg.num_surfaces, 2);
  EXPECT_EQ(msg.surfaces[1].id, 1);
  const auto back = FromAffordanceMsg(msg);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].vertices[2], s.vertices[2]);
  EXPECT_EQ(back[0].normal, s.normal);
  EXPECT_DOUBLE_EQ(back[0].area, 0.5);

  auto bad = msg;
  bad.surfaces[0].area = std::numeric_limits<double>::infinity();
  EXPECT_THROW(FromAffordanceMsg(bad), InputError);
  bad = msg;
  bad.surfaces[1].num_vertices = 2;
  bad.surfaces[1].vertices.resize(2);
  EXPECT_THROW(FromAffordanceMsg(bad), InputError);
}

TEST(Convert, ContactPlanRoundTripAndValidation) {
  ContactPlan plan;
  for (int i = 0; i < 3; ++i) {
    WholeBodyState s;
    s.base_position = {0.1 * i, 0.0, 0.45};
    s.base_rpy = {0.0, 0.01, 0.2};
    for (int j = 0; j < 12; ++j) s.joints[j] = 0.01 * j + i;
    for (int leg = 0; leg < kNumLegs; ++leg) s.feet[static_cast<std::size_t>(leg)].position = {leg + 0.5, i * 1.0, 0.0};
    s.moving_leg = i - 1;
    plan.states.push_back(s);
  }
  const auto msg = ToContactPlanMsg(plan, 11, 3);
  EXPECT_EQ(msg.request_id, 3);
  const ContactPlan back = FromContactPlanMsg(msg);
  ASSERT_EQ(back.states.size(), 3u);
  EXPECT_EQ(back.states[2].joints, plan.states[2].joints);
  EXPECT_EQ(back.states[1].feet[3].position, plan.states[1].feet[3].position);
  EXPECT_EQ(back.states[0].moving_leg, -1);
  EXPECT_EQ(back.states[2].moving_leg, 1);

  auto bad = msg;
  bad.states[1].moving_leg = 4;
  EXPECT_THROW(FromContactPlanMsg(bad), InputError);
  bad = msg;
  bad.states[0].joint_position[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(FromContactPlanMsg(bad), InputError);
}

}  // namespace
}  // namespace rbcp::transport
