#pragma once
/// Rigid poses from roll, pitch and yaw, and the base pose of a whole-body state.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rbcp/core/contact_plan.h"

namespace rbcp {

/// Rotation from roll, pitch, yaw [rad], applied as Rz(yaw) * Ry(pitch) * Rx(roll).
Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy);

/// Roll, pitch, yaw [rad] of a rotation R = Rz(yaw) * Ry(pitch) * Rx(roll), pitch in [-pi/2, pi/2].
Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R);

/// The pose (frame to world) with translation `position` and rotation RotationFromRpy(rpy).
Eigen::Isometry3d PoseFromRpy(const Eigen::Vector3d& position, const Eigen::Vector3d& rpy);

/// Base pose of a state (base to world): PoseFromRpy(base_position, base_rpy).
Eigen::Isometry3d BasePose(const WholeBodyState& state);

/// The minimum-jerk blend from 0 to 1 at u in [0, 1] (rest to rest), and its rate d/du.
inline double MinJerk(double u) { return u * u * u * (10.0 + u * (-15.0 + 6.0 * u)); }
inline double MinJerkRate(double u) { return 30.0 * u * u * (1.0 - u) * (1.0 - u); }

}  // namespace rbcp
