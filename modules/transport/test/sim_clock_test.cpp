#include "rbcp/transport/sim_clock.h"

#include <gtest/gtest.h>

#include <limits>

namespace rbcp::transport {
namespace {

TEST(SimClockTest, OneMessageWithAWrongTimeDoesNotStopTheClock) {
  SimClock clock;
  EXPECT_EQ(clock.Now(), 0);
  EXPECT_EQ(clock.Input(500, "PLAN_REQUEST"), "") << "before the world, inputs set the time";
  EXPECT_EQ(clock.Now(), 500);
  EXPECT_EQ(clock.World(2'000'000, "ROBOT_STATE"), "");
  EXPECT_EQ(clock.Now(), 2'000'000);
  EXPECT_EQ(clock.Input(std::numeric_limits<int64_t>::max(), "PLAN_REQUEST"),
            "PLAN_REQUEST: utime 9223372036854775807 us is not a simulated time (expected 0 to 10000000000000)");
  EXPECT_EQ(clock.Input(-1, "ROOT_PATH"), "ROOT_PATH: utime -1 us is not a simulated time (expected 0 to 10000000000000)");
  EXPECT_EQ(clock.Input(2'000'000 + 601'000'000, "ROOT_PATH"),
            "ROOT_PATH: utime 603.000 s lies 601.000 s ahead of the simulated time 2.000 s (at most 600.000 s)");
  EXPECT_EQ(clock.Now(), 2'000'000) << "rejected times leave the clock alone";
  EXPECT_EQ(clock.Input(3'000'000, "ROOT_PATH"), "");
  EXPECT_EQ(clock.Now(), 3'000'000);
  EXPECT_EQ(clock.World(2'500'000, "ROBOT_STATE"), "");
  EXPECT_EQ(clock.Now(), 2'500'000) << "the world sets the time";
  EXPECT_EQ(clock.World(0, "TERRAIN"), "");
  EXPECT_EQ(clock.Now(), 0) << "a restarted world counts from 0 again";
  EXPECT_NE(clock.World(std::numeric_limits<int64_t>::min(), "TERRAIN"), "");
  EXPECT_EQ(clock.Now(), 0);
}

TEST(SimClockTest, TheSameWorldMessageOfferedAgainChangesNothing) {
  SimClock clock;
  EXPECT_EQ(clock.World(1'000'000, "ROBOT_STATE"), "");
  EXPECT_EQ(clock.Input(1'200'000, "ROOT_PATH"), "");
  // A node looks at its latest ROBOT_STATE every step: the same state does not set the clock back.
  EXPECT_EQ(clock.World(1'000'000, "ROBOT_STATE"), "");
  EXPECT_EQ(clock.Now(), 1'200'000);
  // A rejected world time is reported once, not at every step.
  EXPECT_NE(clock.World(-5, "ROBOT_STATE"), "");
  EXPECT_EQ(clock.World(-5, "ROBOT_STATE"), "");
  EXPECT_EQ(clock.Now(), 1'200'000);
}

}  // namespace
}  // namespace rbcp::transport
