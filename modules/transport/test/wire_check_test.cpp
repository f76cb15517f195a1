#include "rbcp/transport/wire_check.h"

#include <gtest/gtest.h>

#include <vector>

#include "rbcp/transport/latest_message.h"

namespace rbcp::transport {
namespace {

template <typename Msg>
std::vector<uint8_t> Encode(const Msg& msg) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
  EXPECT_EQ(msg.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return buf;
}

void PutInt32(std::vector<uint8_t>& buf, std::size_t offset, uint32_t v) {
  for (int i = 0; i < 4; ++i) buf[offset + static_cast<std::size_t>(i)] = static_cast<uint8_t>(v >> (24 - 8 * i));
}

/// The layout must consume exactly lcm-gen's encoding: the whole message is accepted, and a
/// message one byte short (the layout would expect a byte that is not there) is not.
template <typename Msg>
void ExpectLayoutMatches(const Msg& msg) {
  const std::vector<uint8_t> buf = Encode(msg);
  EXPECT_FALSE(CheckEncoded<Msg>(buf.data(), buf.size()).has_value());
  EXPECT_TRUE(CheckEncoded<Msg>(buf.data(), buf.size() - 1).has_value());
  Msg back;
  EXPECT_FALSE(DecodeMessage(buf.data(), buf.size(), back).has_value());
  EXPECT_EQ(Encode(back), buf);
}

TEST(WireCheck, EveryLayoutMatchesTheGeneratedEncoding) {
  rbcp_msgs::terrain_mesh_t terrain{};
  terrain.scenario_name = "rubble";
  terrain.num_vertices = 3;
  terrain.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  terrain.num_triangles = 1;
  terrain.triangles = {{0, 1, 2}};
  ExpectLayoutMatches(terrain);

  rbcp_msgs::affordance_set_t set{};
  set.num_surfaces = 2;
  set.surfaces.resize(2);
  for (auto& s : set.surfaces) {
    s.num_vertices = 3;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    s.normal[2] = 1.0;
  }
  set.surfaces[1].num_vertices = 0;
  set.surfaces[1].vertices.clear();
  ExpectLayoutMatches(set);

  ExpectLayoutMatches(rbcp_msgs::plan_request_t{});
  ExpectLayoutMatches(rbcp_msgs::robot_state_t{});
  rbcp_msgs::controller_status_t controller{};
  controller.phase = "swing";
  ExpectLayoutMatches(controller);

  rbcp_msgs::root_path_t path{};
  path.num_points = 2;
  path.points.resize(2);
  ExpectLayoutMatches(path);

  rbcp_msgs::contact_plan_t plan{};
  plan.num_states = 2;
  plan.states.resize(2);
  ExpectLayoutMatches(plan);

  rbcp_msgs::process_status_t status{};
  status.process = "root_planner";
  status.reason = "no path";
  ExpectLayoutMatches(status);

  rbcp_msgs::message_part_t part{};
  part.total_size = 3;
  part.part_count = 1;
  part.num_bytes = 3;
  part.bytes = {1, 2, 3};
  ExpectLayoutMatches(part);

  rbcp_msgs::point_cloud_t cloud{};
  cloud.sensor = "front_camera";
  cloud.base_orientation[0] = 1.0;
  cloud.num_points = 2;
  cloud.points = {{1.0f, 0.0f, 0.5f}, {2.0f, 0.1f, -0.2f}};
  ExpectLayoutMatches(cloud);

  rbcp_msgs::elevation_map_t map{};
  map.num_x = 2;
  map.num_y = 1;
  map.num_cells = 2;
  map.height = {0.1f, 0.2f};
  map.variance = {1e-4f, 2e-4f};
  ExpectLayoutMatches(map);
}

/// A terrain of a few bytes whose vertex count claims 2^31 - 1 vertices (48 GB as lcm-gen decodes it).
std::vector<uint8_t> TerrainClaimingHugeCount() {
  rbcp_msgs::terrain_mesh_t msg{};
  std::vector<uint8_t> buf = Encode(msg);
  // After the 8-byte fingerprint, the 8-byte utime, the empty string (4-byte length + NUL) and
  // the 8-byte terrain_id.
  PutInt32(buf, 8 + 8 + 4 + 1 + 8, 0x7fffffffu);
  return buf;
}

TEST(WireCheck, AHugeClaimedCountIsRejectedBeforeDecoding) {
  const std::vector<uint8_t> buf = TerrainClaimingHugeCount();
  EXPECT_LT(buf.size(), 40u);
  const std::optional<std::string> problem = CheckEncoded<rbcp_msgs::terrain_mesh_t>(buf.data(), buf.size());
  EXPECT_EQ(problem, "terrain_mesh_t: num_vertices 2147483647 claims at least 51539607528 bytes of vertices, 4 remain");
  rbcp_msgs::terrain_mesh_t msg;
  EXPECT_EQ(DecodeMessage(buf.data(), buf.size(), msg), problem);
  EXPECT_TRUE(msg.vertices.empty()) << "nothing decoded, nothing allocated";
}

TEST(WireCheck, NestedCountsAndStringsAreCheckedToo) {
  // A set that claims 2^31 - 1 surfaces.
  rbcp_msgs::affordance_set_t set{};
  std::vector<uint8_t> buf = Encode(set);
  PutInt32(buf, 8 + 8 + 8, 0x7fffffffu);  // after the fingerprint, utime and terrain_id
  EXPECT_EQ(CheckEncoded<rbcp_msgs::affordance_set_t>(buf.data(), buf.size()),
            "affordance_set_t: num_surfaces 2147483647 claims at least 85899345880 bytes of surfaces, 0 remain");

  // One surface whose vertex count claims far more than the message holds.
  set.num_surfaces = 1;
  set.surfaces.resize(1);
  buf = Encode(set);
  PutInt32(buf, 8 + 8 + 8 + 4 + 4, 1000000);
  EXPECT_EQ(CheckEncoded<rbcp_msgs::affordance_set_t>(buf.data(), buf.size()),
            "affordance_set_t.surfaces[0]: affordance_surface_t: num_vertices 1000000 claims at least 24000000 bytes "
            "of vertices, 32 remain");

  // A status whose string length is 0 (lcm-gen would take length - 1 characters) or huge.
  rbcp_msgs::process_status_t status{};
  buf = Encode(status);
  PutInt32(buf, 8 + 8, 0);
  EXPECT_EQ(CheckEncoded<rbcp_msgs::process_status_t>(buf.data(), buf.size()),
            "process_status_t: process has length 0, expected at least 1 (the terminating NUL)");
  PutInt32(buf, 8 + 8, 0x7fffffffu);
  EXPECT_EQ(CheckEncoded<rbcp_msgs::process_status_t>(buf.data(), buf.size()),
            "process_status_t: process needs 2147483647 bytes, 35 remain");
}

TEST(WireCheck, ANegativeCountOrAnotherTypeIsRejected) {
  std::vector<uint8_t> buf = Encode(rbcp_msgs::root_path_t{});
  // After the fingerprint, utime, request_id, terrain_id and the reaches_goal byte.
  PutInt32(buf, 8 + 8 + 8 + 8 + 1, 0xfffffffbu);
  EXPECT_EQ(CheckEncoded<rbcp_msgs::root_path_t>(buf.data(), buf.size()), "root_path_t: num_points -5 is negative");
  buf = Encode(rbcp_msgs::plan_request_t{});
  EXPECT_EQ(CheckEncoded<rbcp_msgs::root_path_t>(buf.data(), buf.size()),
            "not a root_path_t (its fingerprint differs: another type or garbage)");
  EXPECT_EQ(CheckEncoded<rbcp_msgs::root_path_t>(buf.data(), 3),
            "root_path_t: 3 bytes, shorter than the type's fingerprint");
}

TEST(LatestMessage, AHugeClaimedCountIsADecodeErrorNamingTheChannel) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  LatestMessage<rbcp_msgs::terrain_mesh_t> latest(lcm, "TERRAIN");
  const std::vector<uint8_t> bad = TerrainClaimingHugeCount();
  lcm.publish("TERRAIN", bad.data(), static_cast<unsigned>(bad.size()));
  while (lcm.handleTimeout(0) > 0) {
  }
  EXPECT_FALSE(latest.Take().has_value());
  const auto error = latest.TakeDecodeError();
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->rfind("cannot decode TERRAIN (", 0), 0u) << *error;
  EXPECT_NE(error->find("num_vertices 2147483647"), std::string::npos) << *error;

  // The next valid message is taken as usual.
  rbcp_msgs::terrain_mesh_t good{};
  good.utime = 7;
  lcm.publish("TERRAIN", &good);
  while (lcm.handleTimeout(0) > 0) {
  }
  const auto taken = latest.Take();
  ASSERT_TRUE(taken.has_value());
  EXPECT_EQ(taken->utime, 7);
}

TEST(EveryMessage, AStatusWithABadStringLengthIsRejectedAndTheNextHandled) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  std::vector<std::string> processes, rejections;
  EveryMessage<rbcp_msgs::process_status_t> every(
      lcm, "STATUS", [&](const rbcp_msgs::process_status_t& m) { processes.push_back(m.process); },
      [&](const std::string& why) { rejections.push_back(why); });
  rbcp_msgs::process_status_t status{};
  status.process = "root_planner";
  std::vector<uint8_t> bad = Encode(status);
  PutInt32(bad, 8 + 8, 0);  // lcm-gen's decoder would throw std::length_error from inside LCM
  lcm.publish("STATUS", bad.data(), static_cast<unsigned>(bad.size()));
  PutInt32(bad, 8 + 8, 0xffffff00u);  // negative
  lcm.publish("STATUS", bad.data(), static_cast<unsigned>(bad.size()));
  lcm.publish("STATUS", &status);
  while (lcm.handleTimeout(0) > 0) {
  }
  EXPECT_EQ(processes, std::vector<std::string>{"root_planner"});
  ASSERT_EQ(rejections.size(), 2u);
  EXPECT_EQ(rejections[0], "cannot decode STATUS (67 bytes): process_status_t: process has length 0, expected at least 1 "
                           "(the terminating NUL)");
  EXPECT_EQ(every.rejected(), 2);
}

}  // namespace
}  // namespace rbcp::transport
