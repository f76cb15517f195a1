#include "rbcp/transport/sim_clock.h"

#include <gtest/gtest.h>

#include <limits>

namespace rbcp::transport {
namespace {

/// What the clock said of a time: "taken" or why it was rejected.
std::string Said(const std::optional<RejectedTime>& rejected) { return rejected ? rejected->Describe() : "taken"; }

TEST(SimClockTest, OneMessageWithAWrongTimeDoesNotStopTheClock) {
  SimClock clock;
  EXPECT_EQ(clock.Now(), 0);
  EXPECT_EQ(Said(clock.Input(500, "PLAN_REQUEST")), "taken") << "before the world, inputs set the time";
  EXPECT_EQ(clock.Now(), 500);
  EXPECT_EQ(Said(clock.World(2'000'000, "ROBOT_STATE")), "taken");
  EXPECT_EQ(clock.Now(), 2'000'000);
  EXPECT_EQ(Said(clock.Input(std::numeric_limits<int64_t>::max(), "PLAN_REQUEST")),
            "PLAN_REQUEST: utime 9223372036854775807 us is not a simulated time (expected 0 to 10000000000000)");
  EXPECT_EQ(Said(clock.Input(-1, "ROOT_PATH")), "ROOT_PATH: utime -1 us is not a simulated time (expected 0 to 10000000000000)");
  const std::optional<RejectedTime> ahead = clock.Input(2'000'000 + 601'000'000, "ROOT_PATH");
  ASSERT_TRUE(ahead.has_value());
  EXPECT_EQ(ahead->kind, RejectedTime::Kind::kTooFarAhead);
  EXPECT_EQ(ahead->Describe(),
            "ROOT_PATH: utime 603.000 s lies 601.000 s ahead of the simulated time 2.000 s (at most 600.000 s)");
  EXPECT_EQ(clock.Now(), 2'000'000) << "rejected times leave the clock alone";
  EXPECT_EQ(Said(clock.Input(3'000'000, "ROOT_PATH")), "taken");
  EXPECT_EQ(clock.Now(), 3'000'000);
  EXPECT_EQ(Said(clock.World(2'500'000, "ROBOT_STATE")), "taken");
  EXPECT_EQ(clock.Now(), 2'500'000) << "the world sets the time";
  EXPECT_EQ(Said(clock.World(0, "TERRAIN")), "taken");
  EXPECT_EQ(clock.Now(), 0) << "a restarted world counts from 0 again";
  EXPECT_NE(Said(clock.World(std::numeric_limits<int64_t>::min(), "TERRAIN")), "taken");
  EXPECT_EQ(clock.Now(), 0);
}

TEST(SimClockTest, TheSameWorldMessageOfferedAgainChangesNothing) {
  SimClock clock;
  EXPECT_EQ(Said(clock.World(1'000'000, "ROBOT_STATE")), "taken");
  EXPECT_EQ(Said(clock.Input(1'200'000, "ROOT_PATH")), "taken");
  // A node looks at its latest ROBOT_STATE every step: the same state does not set the clock back.
  EXPECT_EQ(Said(clock.World(1'000'000, "ROBOT_STATE")), "taken");
  EXPECT_EQ(clock.Now(), 1'200'000);
  // A rejected world time is reported once, not at every step.
  EXPECT_NE(Said(clock.World(-5, "ROBOT_STATE")), "taken");
  EXPECT_EQ(Said(clock.World(-5, "ROBOT_STATE")), "taken");
  EXPECT_EQ(clock.Now(), 1'200'000);
}

}  // namespace
}  // namespace rbcp::transport
