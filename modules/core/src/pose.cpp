#include "rbcp/core/pose.h"

#include <algorithm>
#include <cmath>

namespace rbcp {

Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  return Eigen::Vector3d(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
}

Eigen::Isometry3d PoseFromRpy(const Eigen::Vector3d& position, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = RotationFromRpy(rpy);
  T.translation() = position;
  return T;
}

Eigen::Isometry3d BasePose(const WholeBodyState& state) { return PoseFromRpy(state.base_position, state.base_rpy); }

}  // namespace rbcp
