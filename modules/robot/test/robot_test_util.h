#pragma once
// Shared helpers of the robot model tests.

#include <Eigen/Geometry>
#include <random>
#include <string>

#include "rbcp/robot/robot_model.h"

namespace rbcp::test {

inline std::string ConfigDir() { return std::string(RBCP_SOURCE_DIR) + "/config"; }

/// The shipped ANYmal B model, loaded once per test program.
inline const RobotModel& Anymal() {
  static const RobotModel model = RobotModel::LoadDefault(ConfigDir());
  return model;
}

/// Leg joints drawn uniformly inside the planning bounds.
inline Eigen::Vector3d SampleLegJoints(const RobotModel& model, Leg leg, std::mt19937& rng) {
  const Eigen::Vector3d lo = model.LegLowerBounds(leg);
  const Eigen::Vector3d hi = model.LegUpperBounds(leg);
  Eigen::Vector3d q;
  for (int j = 0; j < 3; ++j) q[j] = std::uniform_real_distribution<double>(lo[j], hi[j])(rng);
  return q;
}

/// All twelve joints drawn as SampleLegJoints does, leg by leg in the order LF, RF, LH, RH.
inline JointVector SampleJoints(const RobotModel& model, std::mt19937& rng) {
  JointVector q;
  for (Leg leg : kAllLegs) SetLegJoints(q, leg, SampleLegJoints(model, leg, rng));
  return q;
}

/// A base-frame point expressed in the leg's HIP frame (the frame turned by HAA).
inline Eigen::Vector3d InHipFrame(const RobotModel& model, Leg leg, double q_haa, const Eigen::Vector3d& p_base) {
  return Eigen::AngleAxisd(-q_haa, Eigen::Vector3d::UnitX()) * (p_base - model.HipPosition(leg));
}

}  // namespace rbcp::test
