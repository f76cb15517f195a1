// The run of a replanning loop rebuilt from its messages: the walked plan, the replans and their
// latency, the trace.
#include "rbcp/nodes/run_record.h"

#include <gtest/gtest.h>

#include "rbcp/core/error.h"
#include "rbcp/transport/convert.h"

namespace rbcp::nodes {
namespace {

/// A plan of `n` steps whose states are told apart by their base x: first_x, first_x + 0.1, ...
ContactPlan Plan(int n, double first_x, bool reaches_goal) {
  ContactPlan plan;
  plan.reaches_goal = reaches_goal;
  for (int i = 0; i <= n; ++i) {
    WholeBodyState s;
    s.base_position = {first_x + 0.1 * i, 0.0, 0.45};
    s.moving_leg = i == 0 ? -1 : i % kNumLegs;
    plan.states.push_back(s);
  }
  return plan;
}

/// The controller's status and the robot's state at `utime`, received at receive_us, in the order
/// the simulator sends them; a waiting robot waits since that utime.
void Feed(RunRecord& run, int64_t receive_us, int64_t utime, int64_t plan_seq, int steps_done, bool waiting) {
  RobotState s;
  s.t = static_cast<double>(utime) * 1e-6;
  ControllerProgress p;
  p.plan_seq = plan_seq;
  p.steps_done = steps_done;
  if (waiting) p.awaiting_since = utime;
  run.OnControllerStatus(receive_us, transport::ToControllerStatusMsg(utime, p));
  run.OnRobotState(receive_us, transport::ToRobotStateMsg(s));
}

TEST(RunRecord, RebuildsTheWalkedPlanAndTheReplanLatency) {
  RunRecord run(20.0);
  // The robot waits at t = 0; plan 1 (3 steps) answers 50 ms later (the first plan: no replan).
  Feed(run, 1000, 0, 0, 0, true);
  run.OnContactPlan(51000, transport::ToContactPlanMsg(Plan(3, 0.0, false), 0, 1, 9, 1, 0));
  // It walks one step of plan 1 and waits; plan 2 answers in 4 ms, from that wait.
  Feed(run, 60000, 100000, 1, 0, false);
  Feed(run, 70000, 2000000, 1, 1, true);
  Feed(run, 72000, 2000000, 1, 1, true);  // the same wait again (the world stands still)
  run.OnContactPlan(74000, transport::ToContactPlanMsg(Plan(2, 0.1, true), 0, 1, 9, 2, 2000000));
  // A stale plan (from the first wait) is no answer and no replan.
  run.OnContactPlan(75000, transport::ToContactPlanMsg(Plan(3, 0.0, false), 0, 1, 9, 3, 0));
  // Plan 2 is walked to the goal.
  Feed(run, 80000, 2002500, 2, 1, false);
  Feed(run, 90000, 6000000, 2, 3, false);

  EXPECT_EQ(run.Plans(), 3);
  EXPECT_EQ(run.GoalPlans(), 1);
  // The start-up: from the first message (1 ms) until the robot walks the first plan (60 ms).
  // Then it waits from the statuses received at 70 ms and 72 ms until 80 ms: 10 ms of the walk's
  // 30 ms.
  EXPECT_NEAR(run.StartupWallS(), 0.059, 1e-12);
  EXPECT_NEAR(run.WaitingWallS(), 0.010, 1e-12);
  EXPECT_NEAR(run.WalkWallS(), 0.030, 1e-12);
  EXPECT_NEAR(run.WaitingShare(), 10.0 / 30.0, 1e-12);
  ASSERT_EQ(run.LatenciesMs().size(), 1u);
  EXPECT_DOUBLE_EQ(run.LatenciesMs()[0], 4.0);
  ASSERT_EQ(run.LatencyTimesS().size(), 1u);
  EXPECT_DOUBLE_EQ(run.LatencyTimesS()[0], 2.0) << "the replan started from the state at 2 s";
  EXPECT_EQ(run.UnansweredWaits(), 0);
  EXPECT_EQ(run.Latest()->utime, 6000000);

  const ContactPlan walked = run.ExecutedPlan();
  ASSERT_EQ(walked.states.size(), 4u) << "plan 1's start and one step, then plan 2's two steps";
  EXPECT_DOUBLE_EQ(walked.states[0].base_position.x(), 0.0);
  EXPECT_DOUBLE_EQ(walked.states[1].base_position.x(), 0.1);
  EXPECT_DOUBLE_EQ(walked.states[2].base_position.x(), 0.2);
  EXPECT_DOUBLE_EQ(walked.states[3].base_position.x(), 0.3);
  EXPECT_TRUE(walked.reaches_goal);

  // The trace keeps one state per 50 ms of simulated time.
  ASSERT_EQ(run.Trace().size(), 4u);
  EXPECT_EQ(run.Trace()[1].state.utime, 100000);
  EXPECT_EQ(run.Trace()[2].state.utime, 2000000);
  ASSERT_TRUE(run.Trace()[2].controller.has_value()) << "each state with its controller's status";
  EXPECT_TRUE(run.Trace()[2].controller->awaiting_plan);
}

TEST(RunRecord, AWaitWithNoAnswerIsCountedAndAWalkedPlanMustHaveBeenReceived) {
  RunRecord run;
  Feed(run, 0, 0, 0, 0, true);
  Feed(run, 10, 500000, 0, 0, true);  // a second wait: the first got no plan
  EXPECT_EQ(run.UnansweredWaits(), 2);
  Feed(run, 20, 600000, 4, 0, false);  // walking plan 4, never received
  EXPECT_THROW(run.ExecutedPlan(), InputError);
  // Asked to, the record leaves the plan out and names it.
  std::vector<std::string> missing;
  EXPECT_TRUE(run.ExecutedPlan(&missing).states.empty());
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0], "plan 4 was walked but never received");
}

TEST(RunRecord, Percentiles) {
  EXPECT_DOUBLE_EQ(Percentile({}, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(Percentile({3.0, 1.0, 2.0}, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(Percentile({1.0, 2.0, 3.0, 4.0, 5.0}, 0.95), 4.8);
}

}  // namespace
}  // namespace rbcp::nodes
