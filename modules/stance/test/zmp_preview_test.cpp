// ZMP preview control of the cart-table model: the CoM moves ahead of a step of the reference so
// that the ZMP follows it.
#include "rbcp/stance/zmp_preview.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

ZmpPreviewParams Params() {
  ZmpPreviewParams p;
  p.com_height_m = 0.46;
  p.time_step_s = 0.005;
  p.preview_s = 1.6;
  return p;
}

/// x: 0 for `before_s`, then `step_m`; y: `y_m` throughout; `total_s` long.
std::vector<Eigen::Vector2d> StepReference(double before_s, double step_m, double y_m, double total_s, double dt) {
  std::vector<Eigen::Vector2d> ref;
  for (int k = 0; k * dt < total_s; ++k) ref.emplace_back(k * dt < before_s ? 0.0 : step_m, y_m);
  return ref;
}

TEST(ZmpPreview, TheComMovesAheadOfAStepSoThatTheZmpFollowsIt) {
  const ZmpPreviewModel model(Params());
  const double dt = model.Params().time_step_s;
  const auto ref = StepReference(2.0, 0.1, 0.05, 5.0, dt);
  const ComTrajectory com = PreviewCom(model, Eigen::Vector2d(0.0, 0.05), ref);
  ASSERT_EQ(com.position.size(), ref.size());
  const std::size_t step = static_cast<std::size_t>(std::lround(2.0 / dt));
  // Ahead of the step the CoM already moves towards it: the preview at work.
  EXPECT_GT(com.position[step].x(), 0.01);
  EXPECT_LT(com.position[step - static_cast<std::size_t>(std::lround(1.5 / dt))].x(), 1e-3)
      << "far ahead of the step the reference is not yet seen";
  // The ZMP moves from one support to the other within 0.1 s of the step; elsewhere it stays within
  // 5 mm of the reference (1 mm from 1 s after the step), and it never overshoots the span of the
  // reference by more than 5 mm, a fraction of a support polygon's margin.
  const std::size_t transition = static_cast<std::size_t>(std::lround(0.1 / dt));
  for (std::size_t k = 0; k < ref.size(); ++k) {
    EXPECT_GT(com.zmp[k].x(), -0.005) << "at t = " << k * dt << " s";
    EXPECT_LT(com.zmp[k].x(), 0.105) << "at t = " << k * dt << " s";
    if (k + transition > step && k < step + transition) continue;
    const double bound = k >= step + static_cast<std::size_t>(std::lround(1.0 / dt)) ? 1e-3 : 5e-3;
    ASSERT_LT((com.zmp[k] - ref[k]).norm(), bound) << "at t = " << k * dt << " s";
  }
  // It ends at rest above the new ZMP; y never moves.
  EXPECT_NEAR(com.position.back().x(), 0.1, 1e-3);
  EXPECT_NEAR(com.velocity.back().x(), 0.0, 1e-3);
  for (const Eigen::Vector2d& p : com.position) EXPECT_NEAR(p.y(), 0.05, 1e-9);
}

TEST(ZmpPreview, TheZmpOfEachSampleIsTheCartTableZmp) {
  const ZmpPreviewModel model(Params());
  const ComTrajectory com = PreviewCom(model, Eigen::Vector2d::Zero(), StepReference(0.5, 0.2, 0.0, 2.0, 0.005));
  const double h_over_g = 0.46 / 9.81;
  for (std::size_t k = 0; k < com.zmp.size(); ++k) {
    EXPECT_NEAR(com.zmp[k].x(), com.position[k].x() - h_over_g * com.acceleration[k].x(), 1e-12);
  }
}

TEST(ZmpPreview, ThePreviewGainsFadeOverTheWindow) {
  const ZmpPreviewModel model(Params());
  ASSERT_EQ(model.PreviewSteps(), 320);
  const std::vector<double>& g = model.PreviewGains();
  double largest = 0.0;
  for (double v : g) largest = std::max(largest, std::abs(v));
  // The last gain also holds the reference beyond the window; the one before it is the window's own.
  EXPECT_LT(std::abs(g[g.size() - 2]), 1e-3 * largest) << "a window this long sees everything that matters";
}

TEST(ZmpPreview, AMovingComIsBroughtToTheReferenceAndTheRestStartIsTheZeroState) {
  const ZmpPreviewModel model(Params());
  const std::vector<Eigen::Vector2d> ref(600, Eigen::Vector2d(0.1, 0.0));  // 3 s standing at x = 0.1
  ComState moving;
  moving.position = Eigen::Vector2d(0.1, 0.0);
  moving.velocity = Eigen::Vector2d(0.3, -0.1);
  const ComTrajectory com = PreviewCom(model, moving, ref);
  EXPECT_EQ(com.velocity.front(), moving.velocity);
  EXPECT_GT(com.position[1].x(), 0.1) << "the first step goes on with the CoM's velocity";
  EXPECT_NEAR(com.position.back().x(), 0.1, 1e-3);
  EXPECT_NEAR(com.position.back().y(), 0.0, 1e-3);
  EXPECT_LT(com.velocity.back().norm(), 0.005);
  ComState rest;
  rest.position = Eigen::Vector2d(0.1, 0.0);
  EXPECT_EQ(PreviewCom(model, rest, ref).position, PreviewCom(model, Eigen::Vector2d(0.1, 0.0), ref).position);
}

TEST(ZmpPreview, TheErrorSumForAJerkGivesTheFirstSampleThatJerk) {
  const ZmpPreviewModel model(Params());
  const double dt = model.Params().time_step_s;
  std::vector<Eigen::Vector2d> ref(400, Eigen::Vector2d(0.05, -0.02));
  for (std::size_t k = 100; k < ref.size(); ++k) ref[k] = Eigen::Vector2d(0.2, 0.1);  // a step later on
  ComState moving;
  moving.position = Eigen::Vector2d(0.0, 0.01);
  moving.velocity = Eigen::Vector2d(0.2, -0.15);
  moving.acceleration = Eigen::Vector2d(-0.5, 0.8);
  const Eigen::Vector2d jerk(3.0, -4.0);
  moving.zmp_error_sum = ZmpErrorSumForJerk(model, moving, ref, jerk);
  const ComTrajectory com = PreviewCom(model, moving, ref);
  const Eigen::Vector2d first_jerk = (com.acceleration[1] - com.acceleration[0]) / dt;
  EXPECT_NEAR(first_jerk.x(), jerk.x(), 1e-6);
  EXPECT_NEAR(first_jerk.y(), jerk.y(), 1e-6);
  // Another sum gives another jerk: the sum is what sets it.
  moving.zmp_error_sum.setZero();
  const ComTrajectory other = PreviewCom(model, moving, ref);
  EXPECT_GT(((other.acceleration[1] - other.acceleration[0]) / dt - jerk).norm(), 1.0);
  EXPECT_THROW(ZmpErrorSumForJerk(model, moving, ref, Eigen::Vector2d(NAN, 0.0)), InputError);
}

TEST(ZmpPreview, BadParametersAndReferencesAreRejected) {
  ZmpPreviewParams p = Params();
  p.com_height_m = 0.0;
  EXPECT_THROW(ZmpPreviewModel{p}, InputError);
  p = Params();
  p.preview_s = 0.001;  // shorter than a time step
  EXPECT_THROW(ZmpPreviewModel{p}, InputError);
  p = Params();
  p.r_jerk = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ZmpPreviewModel{p}, InputError);
  const ZmpPreviewModel model(Params());
  EXPECT_THROW(PreviewCom(model, Eigen::Vector2d::Zero(), {}), InputError);
  std::vector<Eigen::Vector2d> ref(10, Eigen::Vector2d::Zero());
  ref[3].x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(PreviewCom(model, Eigen::Vector2d::Zero(), ref), InputError);
  ComState fast;
  fast.velocity.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(PreviewCom(model, fast, std::vector<Eigen::Vector2d>(10, Eigen::Vector2d::Zero())), InputError);
}

}  // namespace
}  // namespace rbcp
