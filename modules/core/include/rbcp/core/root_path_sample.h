#pragma once
/// A sample of a root (trunk) path: the root planner's output, the contact planner's input.

#include <Eigen/Core>

namespace rbcp {

/// One root state on a path.
struct RootPathSample {
  double t = 0.0;                               ///< time from the path start [s]
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  ///< base position, world frame [m]
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  ///< base velocity, world frame [m/s]
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< base acceleration, world frame [m/s^2]
  double yaw = 0.0;                             ///< heading about world z [rad], in (-pi, pi]
  double rest_yaw = 0.0;                        ///< heading the trunk would keep at rest [rad]
};

}  // namespace rbcp
