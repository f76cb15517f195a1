// The walking pattern of a crawl: support phases on a clock, the ZMP reference, and a CoM that
// moves while the legs swing with its ZMP inside the support.
#include "rbcp/stance/walking_pattern.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "rbcp/core/error.h"
#include "rbcp/core/leg.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "rbcp/stance/swing_trajectory.h"

namespace rbcp {
namespace {

/// Feet at (+-0.36, +-0.26) on flat ground, then `steps` steps of `stride` forward in the crawl
/// order LF, RH, RF, LH (only the feet matter to the pattern).
ContactPlan Crawl(int steps, double stride) {
  ContactPlan plan;
  WholeBodyState start;
  for (Leg leg : kAllLegs) {
    const bool front = leg == Leg::kLF || leg == Leg::kRF, left = leg == Leg::kLF || leg == Leg::kLH;
    start.feet[static_cast<std::size_t>(Index(leg))].position = Eigen::Vector3d(front ? 0.36 : -0.36, left ? 0.26 : -0.26, 0.0);
  }
  plan.states.push_back(start);
  const std::array<Leg, 4> order = {Leg::kLF, Leg::kRH, Leg::kRF, Leg::kLH};
  for (int k = 0; k < steps; ++k) {
    WholeBodyState next = plan.states.back();
    next.moving_leg = Index(order[static_cast<std::size_t>(k % 4)]);
    next.feet[static_cast<std::size_t>(next.moving_leg)].position.x() += stride;
    plan.states.push_back(next);
  }
  return plan;
}

ZmpPreviewModel Model() {
  ZmpPreviewParams p;
  p.com_height_m = 0.46;
  p.time_step_s = 0.005;
  p.preview_s = 1.6;
  return ZmpPreviewModel(p);
}

GaitTiming Timing() {
  GaitTiming t;
  t.start_s = 1.0;
  t.zmp_margin_m = 0.08;
  t.swing_s = 0.5;
  t.four_foot_s = 0.2;
  t.zmp_speed_mps = 10.0;  // four-foot phases of four_foot_s
  t.load_s = 0.05;
  t.unload_s = 0.08;
  t.base_rise_mps = 10.0;
  t.base_turn_radps = 10.0;
  t.final_s = 1.0;
  return t;
}

TEST(WalkingPattern, TheComMovesWhileTheLegsSwingWithItsZmpInsideTheSupport) {
  const ContactPlan plan = Crawl(8, 0.1);
  const WalkingPattern pattern = PlanWalkingPattern(plan, Timing(), Model(), Eigen::Vector2d::Zero());
  ASSERT_EQ(pattern.phases.size(), 2u * 8u + 1u);
  EXPECT_NEAR(pattern.Duration(), 1.0 + 0.5 + 7 * 0.7 + 0.2 + 1.0, 1e-9);
  for (std::size_t i = 0; i < pattern.phases.size(); ++i) {
    const SupportPhase& phase = pattern.phases[i];
    EXPECT_EQ(phase.polygon.size(), phase.swing_leg < 0 ? 4u : 3u) << "phase " << i;
    if (i > 0) {
      EXPECT_DOUBLE_EQ(phase.start_s, pattern.phases[i - 1].end_s);
    }
  }
  // The ZMP of the CoM trajectory never comes nearer than 5 cm to an edge of the feet down.
  EXPECT_GT(pattern.MinZmpMargin(), 0.05);
  // The base advances during every swing, not only with four feet down (least where the reference
  // reaches the next triangle before the next leg unloads).
  const double dt = pattern.time_step_s;
  for (const SupportPhase& phase : pattern.phases) {
    if (phase.swing_leg < 0) continue;
    const auto at = [&](double t) { return pattern.com.position[static_cast<std::size_t>(std::lround(t / dt))]; };
    EXPECT_GT(at(phase.end_s).x() - at(phase.start_s).x(), 0.005) << "swing at " << phase.start_s << " s";
  }
  // It ends at rest over the centre of the last stance, each foot 0.2 m ahead of where it began.
  EXPECT_NEAR(pattern.com.position.back().x(), 0.2, 1e-3);
  EXPECT_NEAR(pattern.com.position.back().y(), 0.0, 1e-3);
  EXPECT_LT(pattern.com.velocity.back().norm(), 0.005) << "at rest: slower than 5 mm/s";
}

TEST(WalkingPattern, ALegUnloadsWithTheZmpOverTheFeetThatStayAndLoadsBeforeItLeavesTheLastOnes) {
  // Between two swings the leg that touched down takes its load while the ZMP reference is still
  // over the last three feet, and the next leg gives up its load with the reference already over
  // the three that stay down: no ramp asks a foot for a load the ZMP says it must not carry.
  const ContactPlan plan = Crawl(8, 0.1);
  GaitTiming timing = Timing();
  timing.load_s = 0.1;
  timing.unload_s = 0.15;
  timing.zmp_speed_mps = 0.5;  // moves of a few tenths of a second
  timing.zmp_margin_m = 0.03;
  const WalkingPattern pattern = PlanWalkingPattern(plan, timing, Model(), Eigen::Vector2d::Zero());
  const auto margin = [&](const SupportPhase& swing, double t) {
    std::vector<Eigen::Vector3d> feet;
    for (const Eigen::Vector2d& v : swing.polygon) feet.emplace_back(v.x(), v.y(), 0.0);
    const Eigen::Vector2d zmp = pattern.ZmpReferenceAt(t);
    return SupportPolygonMargin(feet, Eigen::Vector3d(zmp.x(), zmp.y(), 0.0));
  };
  for (int i = 2; i <= 8; ++i) {
    const SupportPhase& last = pattern.SwingOf(i - 1);
    const SupportPhase& next = pattern.SwingOf(i);
    EXPECT_GE(next.start_s - last.end_s, timing.load_s + timing.unload_s - 2 * timing.zmp_margin_m / timing.zmp_speed_mps - 1e-9);
    for (double t = last.end_s; t <= last.end_s + timing.load_s; t += 0.01) {
      EXPECT_GE(margin(last, t), -1e-9) << "step " << i << ", " << t - last.end_s << " s after the touchdown";
    }
    for (double t = next.start_s - timing.unload_s; t <= next.start_s; t += 0.01) {
      EXPECT_GE(margin(next, t), -1e-9) << "step " << i << ", " << next.start_s - t << " s before the lift-off";
    }
  }
}

TEST(WalkingPattern, APatternContinuedWhenAFootTouchesDownEarlyGoesOnAsTheWholeOne) {
  // The rest of a plan, taken when step 3's foot is down 0.2 s before its swing's end (a new piece
  // of plan in the loop), starts from the CoM's whole state, the ZMP it follows, and the rest of
  // that swing's time: the CoM then goes on as in the pattern of the whole plan.
  const ContactPlan plan = Crawl(8, 0.1);
  const WalkingPattern whole = PlanWalkingPattern(plan, Timing(), Model(), Eigen::Vector2d::Zero());
  const double touchdown_s = whole.SwingOf(3).end_s - 0.2;
  ContactPlan rest;
  rest.states.assign(plan.states.begin() + 3, plan.states.end());
  rest.states.front().MarkAsStart();
  PatternStart start;
  start.com = whole.ComAt(touchdown_s);
  start.zmp = whole.ZmpReferenceAt(touchdown_s);
  start.hold_s = whole.SwingOf(3).end_s - touchdown_s;
  const WalkingPattern continued = PlanWalkingPattern(rest, Timing(), Model(), start);
  EXPECT_NEAR(continued.SwingOf(1).start_s, whole.SwingOf(4).start_s - touchdown_s, 1e-9);
  double largest_m = 0.0, largest_mps2 = 0.0;
  for (double t = 0.0; t < 1.5; t += 0.01) {
    largest_m = std::max(largest_m, (continued.ComAt(t).position - whole.ComAt(touchdown_s + t).position).norm());
    largest_mps2 =
        std::max(largest_mps2, (continued.ComAt(t).acceleration - whole.ComAt(touchdown_s + t).acceleration).norm());
  }
  EXPECT_LT(largest_m, 0.002);
  EXPECT_LT(largest_mps2, 0.1);
}

TEST(WalkingPattern, APlanThatStepsElsewhereIsWalkedFromRestAfterTheComComesToRest) {
  // The crawl forward is at its third touchdown, its CoM on the way to the triangle of step 4,
  // when a plan comes that steps back instead: another leg first. Going on from the ZMP the CoM
  // followed asks, within tens of milliseconds, for more acceleration than friction gives; from
  // the CoM's capture point it comes to rest, then walks the new plan.
  const ContactPlan plan = Crawl(8, 0.1);
  GaitTiming timing = Timing();
  timing.zmp_speed_mps = 1.0;
  timing.start_s = 0.6;
  const WalkingPattern whole = PlanWalkingPattern(plan, timing, Model(), Eigen::Vector2d::Zero());
  const double touchdown_s = whole.SwingOf(3).end_s;
  ContactPlan back;
  back.states.push_back(plan.states[3]);
  back.states.front().MarkAsStart();
  const std::array<Leg, 4> order = {Leg::kRH, Leg::kLF, Leg::kLH, Leg::kRF};  // step 4 is LH
  for (Leg leg : order) {
    WholeBodyState next = back.states.back();
    next.moving_leg = Index(leg);
    next.feet[static_cast<std::size_t>(next.moving_leg)].position.x() -= 0.1;
    back.states.push_back(next);
  }
  ASSERT_NE(back.states[1].moving_leg, plan.states[4].moving_leg);
  PatternStart start;
  start.com = whole.ComAt(touchdown_s);
  start.zmp = whole.ZmpReferenceAt(touchdown_s);
  ASSERT_GT(start.com.velocity.norm(), 0.05) << "the CoM is moving";
  const auto peak_acceleration = [&](const WalkingPattern& p, double until_s) {
    double peak = 0.0;
    for (double t = 0.0; t <= until_s; t += p.time_step_s) peak = std::max(peak, p.ComAt(t).acceleration.norm());
    return peak;
  };
  const double friction_mps2 = 0.8 * 9.81;
  const WalkingPattern going_on = PlanWalkingPattern(back, timing, Model(), start);
  EXPECT_GT(peak_acceleration(going_on, going_on.SwingOf(1).start_s), friction_mps2);
  start.come_to_rest = true;
  start.hold_s = timing.start_s / 2;
  const WalkingPattern from_rest = PlanWalkingPattern(back, timing, Model(), start);
  EXPECT_LT(peak_acceleration(from_rest, from_rest.Duration()), 0.5 * friction_mps2);
  EXPECT_GT(from_rest.MinZmpMargin(), 0.0);
  // Its ZMP starts at the CoM's capture point, which the CoM then heads for.
  const double omega = std::sqrt(9.81 / 0.46);
  EXPECT_LT((from_rest.ZmpAt(0.0) - (start.com.position + start.com.velocity / omega)).norm(), 1e-9);
  EXPECT_GT((from_rest.ComAt(start.hold_s).position - start.com.position).dot(start.com.velocity), 0.0);
}

TEST(WalkingPattern, DuringASwingTheReferenceKeepsTheMarginNearestTheCentreOfTheFeet) {
  const ContactPlan plan = Crawl(1, 0.1);  // LF swings: RF, LH, RH stay down
  const WalkingPattern pattern = PlanWalkingPattern(plan, Timing(), Model(), Eigen::Vector2d::Zero());
  // The centre of the four feet, (0, 0), lies on the triangle's edge from RF to LH: the reference
  // is 8 cm inside that edge, straight in from the centre.
  const Eigen::Vector2d inward = Eigen::Vector2d(-0.52, -0.72).normalized();
  const std::size_t mid_swing = static_cast<std::size_t>(std::lround((1.0 + 0.25) / pattern.time_step_s));
  EXPECT_LT((pattern.zmp_reference[mid_swing] - 0.08 * inward).norm(), 1e-12);
}

TEST(WalkingPattern, TheNearestPointWithAMarginIsThePointItselfInsideAndTheIncentreInATinyTriangle) {
  const std::array<Eigen::Vector2d, 3> tri = {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(0.0, 1.0)};
  EXPECT_EQ(NearestWithMargin(tri, 0.1, Eigen::Vector2d(0.2, 0.2)), Eigen::Vector2d(0.2, 0.2));
  EXPECT_TRUE(NearestWithMargin(tri, 0.1, Eigen::Vector2d(0.5, -1.0)).isApprox(Eigen::Vector2d(0.5, 0.1)));
  EXPECT_EQ(NearestWithMargin(tri, 0.5, Eigen::Vector2d(0.9, 0.9)), TriangleIncentre(tri));
  const Eigen::Vector2d i = TriangleIncentre(tri);
  EXPECT_NEAR(i.x(), i.y(), 1e-15);
  EXPECT_NEAR(i.x(), 1.0 - std::sqrt(0.5), 1e-12) << "the inradius of the unit right triangle";
}

TEST(WalkingPattern, AStepSwingsForTheDurationOfItsOwnSwingPath) {
  ContactPlan plan = Crawl(2, 0.1);
  plan.states[1].swing_apex_z = 0.3;  // a high swing
  SwingPathConfig swing;
  swing.speed_mps = 0.8;
  swing.min_duration_s = 0.45;
  const std::size_t leg = static_cast<std::size_t>(plan.states[1].moving_leg);
  const std::vector<double> durations = {
      SwingTrajectory::Given(plan.states[0].feet[leg].position, plan.states[1].feet[leg].position,
                             plan.states[1].swing_apex_z, plan.states[1].swing_bow, swing)
          .Duration(),
      std::numeric_limits<double>::quiet_NaN()};  // the second step: swing_s
  EXPECT_GT(durations[0], 0.45) << "0.3 m up and down at 0.8 m/s";
  GaitTiming timing = Timing();
  timing.step_swing_s = durations;
  const WalkingPattern pattern = PlanWalkingPattern(plan, timing, Model(), Eigen::Vector2d::Zero());
  ASSERT_EQ(pattern.phases.size(), 5u);
  EXPECT_NEAR(pattern.phases[1].end_s - pattern.phases[1].start_s, durations[0], 1e-12);
  EXPECT_NEAR(pattern.phases[3].end_s - pattern.phases[3].start_s, 0.5, 1e-12) << "swing_s where none is given";
  timing.step_swing_s.pop_back();
  EXPECT_THROW(PlanWalkingPattern(plan, timing, Model(), Eigen::Vector2d::Zero()), InputError);
}

TEST(WalkingPattern, BadPlansAndTimingsAreRejected) {
  const ZmpPreviewModel model = Model();
  EXPECT_THROW(PlanWalkingPattern(Crawl(0, 0.1), Timing(), model, Eigen::Vector2d::Zero()), InputError);
  ContactPlan no_leg = Crawl(2, 0.1);
  no_leg.states[2].moving_leg = -1;
  EXPECT_THROW(PlanWalkingPattern(no_leg, Timing(), model, Eigen::Vector2d::Zero()), InputError);
  GaitTiming zero = Timing();
  zero.four_foot_s = 0.0;
  EXPECT_THROW(PlanWalkingPattern(Crawl(2, 0.1), zero, model, Eigen::Vector2d::Zero()), InputError);
}

}  // namespace
}  // namespace rbcp
