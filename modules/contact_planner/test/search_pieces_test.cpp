// The pieces of the contact search on their own: the keep phase, one step attempt, step merging.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "feet_kept.h"
#include "merge_steps.h"
#include "planner_context.h"
#include "rbcp/core/pose.h"
#include "rbcp/limb_database/limb_database.h"
#include "start_stance.h"
#include "step.h"
#include "test_world.h"

namespace rbcp::contact_planner_detail {
namespace {

using test::Equilibrium;
using test::PlannerConfig;
using test::Robot;
using test::Rules;
using test::SmallDatabase;

/// A planner context on a 6 x 2 m floor (top at z = 0) with a straight path along x from the
/// origin, 1.5 m in 10 s at the nominal base height.
class SearchPieces : public ::testing::Test {
 protected:
  void SetUp() override {
    TriangleMesh floor = MakeBoxMesh(Eigen::Vector3d(6.0, 2.0, 0.5));
    floor.Transform(Eigen::Isometry3d(Eigen::Translation3d(1.0, 0.0, -0.25)));
    terrain_ = floor;
    for (const AffordanceSurface& s : test::ExtractSurfaces(terrain_)) surfaces_.emplace_back(s.vertices, s.normal);
    stance_.SetTerrain(&terrain_);
    std::vector<RootPathSample> samples;
    for (int i = 0; i <= 100; ++i) {
      RootPathSample s;
      s.t = 0.1 * i;
      s.p = Eigen::Vector3d(0.015 * i, 0.0, Robot().NominalBaseHeight());
      samples.push_back(s);
    }
    path_ = std::make_unique<PathTrack>(samples, config_.path_yaw_smoothing_s);
    budget_.Start(600.0);
  }

  /// The node standing at the path start.
  Node Start() {
    const StandingResult standing = StandingAt(ctx_, path_->At(0.0).p, 0.0);
    EXPECT_TRUE(standing.state.has_value()) << standing.failure->Describe();
    Node node;
    node.state = *standing.state;
    node.t = 0.0;
    return node;
  }

  ContactPlannerConfig config_ = PlannerConfig();
  TriangleMesh terrain_;
  std::vector<ConvexPolygon3d> surfaces_;
  StanceChecker stance_{Robot(), Rules()};
  StaticEquilibrium equilibrium_{Robot().TotalMass(), Equilibrium()};
  ContactPlanStats stats_;
  TimeBudget budget_;
  BodyPoseData body_poses_;
  std::vector<AvoidedStep> avoided_;
  PlannerContext ctx_{Robot(),   SmallDatabase(), Equilibrium(), config_,  stance_,    surfaces_,
                      avoided_,  equilibrium_,    stats_,        budget_,  body_poses_};
  std::unique_ptr<PathTrack> path_;
};

TEST_F(SearchPieces, TheTrunkAdvancesOnTheKeptFeetUntilOneCanNoLongerBeKept) {
  const Node start = Start();
  const KeptFeetAdvance keep = AdvanceWithFeetKept(ctx_, *path_, start);
  EXPECT_FALSE(keep.reached_end);
  EXPECT_GT(keep.t_last_keepable, start.t) << "the trunk advances some way on the standing feet";
  EXPECT_LT(keep.t_last_keepable, path_->End());
  EXPECT_TRUE(KeepAt(ctx_, *path_, start, keep.t_last_keepable).ok());
  const KeepCheck beyond = KeepAt(ctx_, *path_, start, keep.t_last_keepable + 2.0 * config_.step_time_resolution_s);
  ASSERT_FALSE(beyond.ok());
  EXPECT_FALSE(beyond.failure->Describe().empty());
  // Every leg ranked once, the failing ones first.
  ASSERT_EQ(keep.ranking.size(), static_cast<std::size_t>(kNumLegs));
  EXPECT_TRUE(keep.ranking.front().failing);
  for (std::size_t k = 1; k < keep.ranking.size(); ++k) {
    EXPECT_FALSE(!keep.ranking[k - 1].failing && keep.ranking[k].failing) << "failing legs first";
  }
  EXPECT_GT(stats_.keep_checks, 0);
}

TEST_F(SearchPieces, AStepAttemptFindsAFootholdTheControllerCanWalkTo) {
  const Node start = Start();
  const KeptFeetAdvance keep = AdvanceWithFeetKept(ctx_, *path_, start);
  const Leg leg = keep.ranking.front().leg;
  const StepAttempt attempt =
      TryStep(ctx_, *path_, start, Node::Option{leg, keep.t_last_keepable, 0, false, 0}, CrawlProfile{});
  ASSERT_EQ(attempt.outcome(), StepOutcome::kFound) << attempt.failure->Describe();
  const WholeBodyState& after = attempt.child.state;
  EXPECT_EQ(after.moving_leg, Index(leg));
  EXPECT_DOUBLE_EQ(attempt.child.t, keep.t_last_keepable);
  const std::size_t i = static_cast<std::size_t>(Index(leg));
  EXPECT_GT(after.feet[i].position.x(), start.state.feet[i].position.x()) << "the foot steps ahead";
  for (std::size_t other = 0; other < after.feet.size(); ++other) {
    if (other != i) {
      EXPECT_EQ(after.feet[other].position, start.state.feet[other].position);
    }
  }
  const StanceVerdict verdict = stance_.CheckStep(start.state, after);
  EXPECT_TRUE(verdict.ok()) << verdict.Describe();
  EXPECT_GT(stats_.swing_checks, 0) << "the swing was checked";
}

TEST_F(SearchPieces, AStepAttemptFailsWithAReasonWhereNoStanceIsValid) {
  // Far along the path the trunk has left the standing feet behind: no stance before lift-off.
  const Node start = Start();
  const StepAttempt attempt =
      TryStep(ctx_, *path_, start, Node::Option{Leg::kLF, 0.8 * path_->End(), 0, false, 0}, CrawlProfile{});
  EXPECT_EQ(attempt.outcome(), StepOutcome::kPoseInvalid);
  ASSERT_TRUE(attempt.failure.has_value());
  EXPECT_EQ(attempt.failure->kind, StepFailure::Kind::kStanceOutOfReach) << attempt.failure->Describe();
  EXPECT_NE(attempt.failure->Describe().find("out of reach"), std::string::npos) << attempt.failure->Describe();
}

TEST_F(SearchPieces, MergingRemovesAStepAndKeepsEveryStepWalkable) {
  // LF steps 6 cm, RH steps, then LF another 6 cm, the trunk advancing 4.5 cm along the path
  // before each step: LF may stand on its first foothold until it steps 12 cm at once.
  std::vector<WholeBodyState> states = {Start().state};
  const auto step = [&](Leg leg, double dx) {
    Node parent;
    parent.state = states.back();
    // The body shift of the swing, as the search finds it.
    const PathPose pose = path_->At(0.3 * static_cast<double>(states.size()));
    const SwingShiftResult shifted = SwingShift(ctx_, pose, parent, leg, Eigen::Vector3d::Zero());
    ASSERT_TRUE(shifted.ok()) << shifted.failure->Describe();
    WholeBodyState next = states.back();
    next.moving_leg = Index(leg);
    next.feet[static_cast<std::size_t>(Index(leg))].position.x() += dx;
    next.base_position = shifted.base.base_W.translation();
    next.base_rpy = shifted.base.rpy;
    const std::optional<JointVector> q = stance_.SolveStance(shifted.base.base_W, next.feet, -1);
    ASSERT_TRUE(q.has_value());
    next.joints = *q;
    states.push_back(next);
  };
  step(Leg::kLF, 0.06);
  step(Leg::kRH, 0.06);
  step(Leg::kLF, 0.06);
  ASSERT_EQ(states.size(), 4u);
  for (std::size_t k = 1; k < states.size(); ++k) {
    const StanceVerdict v = stance_.CheckStep(states[k - 1], states[k]);
    ASSERT_TRUE(v.ok()) << "state " << k << ": " << v.Describe();
  }
  int removed = 0;
  const std::vector<WholeBodyState> merged = MergeSteps(ctx_, states, &removed);
  EXPECT_EQ(removed, 1);
  ASSERT_EQ(merged.size(), states.size() - 1);
  EXPECT_EQ(merged.front().feet[0].position, states.front().feet[0].position);
  for (std::size_t leg = 0; leg < static_cast<std::size_t>(kNumLegs); ++leg) {
    EXPECT_EQ(merged.back().feet[leg].position, states.back().feet[leg].position) << "each leg's last foothold";
  }
  for (std::size_t k = 1; k < merged.size(); ++k) {
    const StanceVerdict v = stance_.CheckStep(merged[k - 1], merged[k]);
    EXPECT_TRUE(v.ok()) << "state " << k << ": " << v.Describe();
  }

  // With LF's last foothold avoided from any stance (its dynamic walk failed there), no merge
  // steps there earlier: the steps stay as they were.
  const auto lf_step = std::find_if(merged.begin() + 1, merged.end(),
                                    [](const WholeBodyState& s) { return s.moving_leg == Index(Leg::kLF); });
  ASSERT_NE(lf_step, merged.end());
  avoided_.push_back(AvoidedStep::Of(*(lf_step - 1), *lf_step, false));
  EXPECT_TRUE(IsAvoided(avoided_, *(lf_step - 1), *lf_step));
  EXPECT_EQ(MergeSteps(ctx_, states, &removed).size(), states.size());
  EXPECT_EQ(removed, 0);
}

TEST(AvoidedStepTest, IsTheLegsFootholdFromThatStanceOrFromAnyWithinThreeCentimetres) {
  WholeBodyState before;
  for (std::size_t i = 0; i < static_cast<std::size_t>(kNumLegs); ++i) {
    before.feet[i].position = Eigen::Vector3d(i < 2 ? 0.3 : -0.3, i % 2 == 0 ? 0.2 : -0.2, 0.0);
  }
  WholeBodyState after = before;
  after.moving_leg = Index(Leg::kRF);
  after.feet[1].position.x() += 0.2;
  const AvoidedStep from_before = AvoidedStep::Of(before, after);
  const AvoidedStep from_any = AvoidedStep::Of(before, after, false);
  EXPECT_TRUE(from_before.Is(before, after));

  WholeBodyState near = after;  // the foothold 2 cm off
  near.feet[1].position.y() += 0.02;
  EXPECT_TRUE(from_before.Is(before, near));
  WholeBodyState far = after;  // 4 cm off
  far.feet[1].position.y() += 0.04;
  EXPECT_FALSE(from_before.Is(before, far));
  EXPECT_FALSE(from_any.Is(before, far));

  WholeBodyState other_stance = before;  // LH stands 5 cm back
  other_stance.feet[2].position.x() -= 0.05;
  EXPECT_FALSE(from_before.Is(other_stance, after));
  EXPECT_TRUE(from_any.Is(other_stance, after));

  WholeBodyState other_leg = after;  // LF to RF's foothold is another step
  other_leg.moving_leg = Index(Leg::kLF);
  EXPECT_FALSE(from_any.Is(before, other_leg));
  EXPECT_FALSE(from_before == from_any);
}

TEST(StepFailureTest, SaysWhatFailedWithItsNumbersAndHowTheStepEnded) {
  StepFailure none(StepFailure::Kind::kNoFoothold);
  none.count = 12;
  none.last = CandidateFailure(CandidateFailure::Kind::kRobustness);
  none.last->robustness_N = 2.104;
  EXPECT_EQ(none.Describe(), "no valid foothold among 12 candidates (last rejected: robustness 2.10 N)");
  EXPECT_EQ(none.Outcome(), StepOutcome::kNoCandidate);
  EXPECT_EQ(StepFailure(StepFailure::Kind::kNoFoothold).Describe(),
            "no valid foothold among 0 candidates (last rejected: no database sample near a contact surface)");

  StepFailure capped(StepFailure::Kind::kStabilityCap);
  capped.count = 3;
  capped.last = CandidateFailure(CandidateFailure::Kind::kKinematics);
  EXPECT_EQ(capped.Describe(), "no stable foothold among the 3 best candidates (last: kinematics)");
  EXPECT_EQ(capped.Outcome(), StepOutcome::kCapped);

  StepFailure off_centre(StepFailure::Kind::kCoMNotInside);
  off_centre.margin_m = 0.03;
  EXPECT_EQ(off_centre.Describe(), "CoM cannot be shifted 0.030 m inside the swing support triangle");
  EXPECT_EQ(off_centre.Outcome(), StepOutcome::kPoseInvalid);

  StanceVerdict torque;
  torque.check = StanceCheck::kTorque;
  torque.detail = "LF_KFE 45.0 Nm";
  EXPECT_EQ(StepFailure(StepFailure::Kind::kLiftOffTorque, torque).Describe(),
            "three-foot stance at lift-off: LF_KFE 45.0 Nm");
}

}  // namespace
}  // namespace rbcp::contact_planner_detail
