#include "rbcp/core/pose.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rbcp {
namespace {

TEST(Pose, RpyMatchesZyxConvention) {
  const Eigen::Matrix3d R = RotationFromRpy({0.0, 0.0, M_PI / 2});
  EXPECT_TRUE((R * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  const Eigen::Matrix3d P = RotationFromRpy({0.0, 0.3, 0.0});
  EXPECT_NEAR((P * Eigen::Vector3d::UnitX()).z(), -std::sin(0.3), 1e-12);
}

TEST(Pose, BasePoseMapsBaseToWorld) {
  WholeBodyState state;
  state.base_position = {1.0, 2.0, 0.5};
  state.base_rpy = {0.0, 0.0, M_PI / 2};
  const Eigen::Isometry3d T = BasePose(state);
  EXPECT_TRUE(T.translation().isApprox(state.base_position, 1e-15));
  EXPECT_TRUE((T * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(1.0, 3.0, 0.5), 1e-12));
  EXPECT_TRUE(T.linear().isApprox(RotationFromRpy(state.base_rpy), 1e-15));
}

}  // namespace
}  // namespace rbcp
