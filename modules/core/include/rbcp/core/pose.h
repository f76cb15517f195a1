#pragma once
/// Rigid poses from roll, pitch and yaw, and the base pose of a whole-body state.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rbcp/core/contact_plan.h"

namespace rbcp {

/// Rotation from roll, pitch, yaw [rad], applied as Rz(yaw) * Ry(pitch) * Rx(roll).
Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy);

/// Base pose of a state (base to world): translation base_position, rotation
/// RotationFromRpy(base_rpy).
Eigen::Isometry3d BasePose(const WholeBodyState& state);

}  // namespace rbcp
