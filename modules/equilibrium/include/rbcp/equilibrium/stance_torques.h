#pragma once
/// Joint torques of a quasi-static stance as the onboard controller holds it: the robot's weight,
/// acting at the CoM, spread over the stance feet by DistributeWrench (the distribution the
/// controller applies), plus each stance leg's own weight. The contact planner and the plan
/// checker use it to keep every stance within what the actuators can command, and the controller
/// to choose base poses that ask less of them.

#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "rbcp/core/contact_plan.h"
#include "rbcp/equilibrium/force_distribution.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {

struct StanceTorques {
  /// The distribution balances the weight (within 2 % of it, and 2 % of it times 0.1 m about
  /// the CoM); false when the CoM is outside what the feet's friction cones can hold.
  bool balanced = false;
  /// Torque [N m] of every joint, by the whole-robot joint index; zero for legs not in stance.
  JointVector tau = JointVector::Zero();
  double max_abs_Nm = 0.0;  ///< largest |tau| over the stance legs
  int worst_joint = -1;     ///< whole-robot index of that joint, -1 with no stance foot
  ForceDistribution forces;
};

/// The feet of a plan state as stance feet (positions and normals as given), all but `skip`'s
/// (-1: all four).
std::vector<StanceFoot> StanceFeet(const std::array<FootContact, kNumLegs>& feet, int skip);

/// Torques of the stance `feet` (contact points and normals, world frame) with the base at
/// `base_W`, joint angles `q` (only the stance legs' are read) and the CoM at `com_W`, accelerating
/// at `com_acceleration_W` (the feet then push m (a - g); zero: standing still).
StanceTorques ComputeStanceTorques(const RobotModel& robot, const Eigen::Isometry3d& base_W, const JointVector& q,
                                   const std::vector<StanceFoot>& feet, const Eigen::Vector3d& com_W,
                                   const ForceDistributionParams& params,
                                   const Eigen::Vector3d& com_acceleration_W = Eigen::Vector3d::Zero());

}  // namespace rbcp
