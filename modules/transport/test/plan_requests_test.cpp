#include "rbcp/transport/plan_requests.h"

#include <gtest/gtest.h>

namespace rbcp::transport {
namespace {

rbcp_msgs::plan_request_t Request(int64_t id, double goal_x) {
  rbcp_msgs::plan_request_t r{};
  r.request_id = id;
  r.use_start = true;
  r.goal_position[0] = goal_x;
  r.seed = 1;
  return r;
}

TEST(PlanRequestsTest, ARequestIsItsIdAndItsQuestion) {
  const auto a = Request(42, 1.0);
  auto again = a;
  again.utime = 5000;
  again.time_budget = 3.0;
  EXPECT_TRUE(SameRequest(a, again)) << "utime and budget do not make another question";
  EXPECT_FALSE(SameRequest(a, Request(43, 1.0)));
  EXPECT_FALSE(SameRequest(a, Request(42, 2.0))) << "the same id for another goal is another request";
  auto from_robot = a;
  from_robot.use_start = false;
  from_robot.start_position[0] = 9.0;
  auto from_robot_elsewhere = from_robot;
  from_robot_elsewhere.start_position[0] = -9.0;
  EXPECT_TRUE(SameRequest(from_robot, from_robot_elsewhere)) << "an unused start does not count";
}

TEST(PlanRequestsTest, ALateRepeatOfASupersededRequestIsNotANewGoal) {
  RequestHistory history;
  EXPECT_EQ(history.Latest(), nullptr);
  const auto high = Request(1'000'000'000'000, 1.0);
  const auto low = Request(7, 2.0);
  history.Take(high);
  EXPECT_FALSE(history.Superseded(low)) << "ids are not ordered: a lower id is a new request";
  history.Take(low);
  EXPECT_TRUE(SameRequest(*history.Latest(), low));
  EXPECT_TRUE(history.Superseded(high)) << "a repeat of the request before is stale";
  EXPECT_FALSE(history.Superseded(low)) << "a repeat of the latest is the latest";
  history.Take(high);  // asked for anew
  EXPECT_TRUE(SameRequest(*history.Latest(), high));
  EXPECT_TRUE(history.Superseded(low));
}

TEST(PlanRequestsTest, TheHistoryIsBounded) {
  RequestHistory history(3);
  for (int64_t id = 1; id <= 5; ++id) history.Take(Request(id, 1.0));
  EXPECT_FALSE(history.Superseded(Request(1, 1.0))) << "forgotten";
  EXPECT_TRUE(history.Superseded(Request(3, 1.0)));
}

}  // namespace
}  // namespace rbcp::transport
