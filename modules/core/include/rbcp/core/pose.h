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

}  // namespace rbcp
