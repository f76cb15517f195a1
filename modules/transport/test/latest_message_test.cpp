#include "rbcp/transport/latest_message.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::transport {
namespace {

TEST(LatestMessage, AFilterKeepsOnlyTheMessagesItAccepts) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  LatestMessage<rbcp_msgs::process_status_t> failures(
      lcm, "S", [](const rbcp_msgs::process_status_t& m) { return m.state == rbcp_msgs::process_status_t::FAILED; });
  rbcp_msgs::process_status_t msg{};
  msg.state = rbcp_msgs::process_status_t::FAILED;
  msg.utime = 1;
  lcm.publish("S", &msg);
  msg.state = rbcp_msgs::process_status_t::ALIVE;  // a heartbeat right after the failure
  msg.utime = 2;
  lcm.publish("S", &msg);
  while (lcm.handleTimeout(0) > 0) {
  }
  const auto taken = failures.Take();
  ASSERT_TRUE(taken.has_value());
  EXPECT_EQ(taken->utime, 1);
  EXPECT_EQ(failures.received(), 1);
}

TEST(StatusReporter, TheBackgroundHeartbeatGoesOnWhileTheProcessIsBusy) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  LatestMessage<rbcp_msgs::process_status_t> status(lcm, "S");
  {
    StatusReporter reporter(lcm, "worker", "S");
    reporter.set_verbose(false);
    reporter.StartBackgroundHeartbeat(0.02);
    reporter.Busy(5, 5);
    // The main thread works (here: sleeps) without publishing; the heartbeat still goes out.
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  while (lcm.handleTimeout(0) > 0) {
  }
  EXPECT_GE(status.received(), 2) << "the BUSY state and at least one heartbeat of it";
  ASSERT_TRUE(status.Latest().has_value());
  EXPECT_EQ(status.Latest()->state, rbcp_msgs::process_status_t::BUSY);
  EXPECT_EQ(status.Latest()->process, "worker");
}

TEST(StatusReporter, AProcessBusyBeyondItsBoundFallsSilentForTheSupervisor) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  LatestMessage<rbcp_msgs::process_status_t> status(lcm, "S");
  const auto drain = [&] {
    while (lcm.handleTimeout(0) > 0) {
    }
  };
  StatusReporter reporter(lcm, "worker", "S");
  reporter.set_verbose(false);
  reporter.StartBackgroundHeartbeat(0.01, 0.05);
  reporter.Busy(5, 5);
  // Stuck: well past the bound, the heartbeat has stopped.
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  drain();
  const int received = status.received();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  drain();
  EXPECT_EQ(status.received(), received) << "no STATUS from a process stuck with one input";
  // Working again: the heartbeat comes back.
  reporter.Ok(6, 5, 1.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  drain();
  EXPECT_GE(status.received(), received + 2) << "the answer and heartbeats of it";
  EXPECT_EQ(status.Latest()->state, rbcp_msgs::process_status_t::OK);
}

TEST(LatestMessage, KeepsOnlyTheNewestAndTakesOnce) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  LatestMessage<rbcp_msgs::process_status_t> latest(lcm, "S");
  for (int i = 1; i <= 3; ++i) {
    rbcp_msgs::process_status_t msg{};
    msg.utime = i;
    lcm.publish("S", &msg);
  }
  while (lcm.handleTimeout(0) > 0) {
  }
  EXPECT_EQ(latest.received(), 3);
  auto taken = latest.Take();
  ASSERT_TRUE(taken.has_value());
  EXPECT_EQ(taken->utime, 3);
  EXPECT_FALSE(latest.Take().has_value());
  EXPECT_EQ(latest.Latest()->utime, 3);
}

TEST(LatestMessage, MalformedBytesBecomeADecodeError) {
  lcm::LCM lcm("memq://");
  LatestMessage<rbcp_msgs::terrain_mesh_t> latest(lcm, "T");
  const char garbage[] = "not an lcm message";
  lcm.publish("T", garbage, sizeof(garbage));
  // A message of another type on the same channel: the fingerprint differs.
  rbcp_msgs::process_status_t other{};
  lcm.publish("T", &other);
  while (lcm.handleTimeout(0) > 0) {
  }
  EXPECT_FALSE(latest.Take().has_value());
  auto error = latest.TakeDecodeError();
  ASSERT_TRUE(error.has_value());
  EXPECT_NE(error->find("cannot decode T"), std::string::npos);
}

TEST(LatestMessage, NegativeArrayCountDoesNotCrash) {
  lcm::LCM lcm("memq://");
  LatestMessage<rbcp_msgs::terrain_mesh_t> latest(lcm, "T");
  rbcp_msgs::terrain_mesh_t msg{};
  msg.num_vertices = 0;
  msg.num_triangles = 0;
  std::vector<uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
  ASSERT_GT(msg.encode(buf.data(), 0, static_cast<int>(buf.size())), 0);
  // num_vertices sits after the 8-byte fingerprint, the 8-byte utime, the string (4-byte
  // length + NUL) and the 8-byte terrain_id: overwrite it with -5 (big-endian).
  const std::size_t offset = 8 + 8 + 4 + 1 + 8;
  buf[offset] = 0xff;
  buf[offset + 1] = 0xff;
  buf[offset + 2] = 0xff;
  buf[offset + 3] = 0xfb;
  lcm.publish("T", buf.data(), static_cast<unsigned>(buf.size()));
  while (lcm.handleTimeout(0) > 0) {
  }
  EXPECT_FALSE(latest.Take().has_value());
  EXPECT_TRUE(latest.TakeDecodeError().has_value());
}

TEST(StatusReporter, PublishesStatesWithCounts) {
  lcm::LCM lcm("memq://");
  LatestMessage<rbcp_msgs::process_status_t> status(lcm, "STATUS");
  StatusReporter reporter(lcm, "unit", "STATUS");
  reporter.set_verbose(false);
  reporter.Ok(10, 9, 1.5);
  reporter.Failed(20, 19, 0.5, "terrain mesh: vertex 2 is not finite");
  while (lcm.handleTimeout(0) > 0) {
  }
  auto last = status.Take();
  ASSERT_TRUE(last.has_value());
  EXPECT_EQ(last->process, "unit");
  EXPECT_EQ(last->state, rbcp_msgs::process_status_t::FAILED);
  EXPECT_EQ(last->reason, "terrain mesh: vertex 2 is not finite");
  EXPECT_EQ(last->handled, 2);
  EXPECT_EQ(last->input_utime, 19);
  EXPECT_STREQ(StatusName(last->state), "failed");
}

}  // namespace
}  // namespace rbcp::transport
