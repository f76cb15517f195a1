#include "rbcp/equilibrium/stance_torques.h"

#include "rbcp/equilibrium/static_equilibrium.h"

namespace rbcp {

std::vector<StanceFoot> StanceFeet(const std::array<FootContact, kNumLegs>& feet, int skip) {
  std::vector<StanceFoot> out;
  for (Leg leg : kAllLegs) {
    if (Index(leg) == skip) continue;
    StanceFoot f;
    f.leg = leg;
    f.position_W = feet[static_cast<std::size_t>(Index(leg))].position;
    f.normal_W = feet[static_cast<std::size_t>(Index(leg))].normal;
    out.push_back(f);
  }
  return out;
}

StanceTorques ComputeStanceTorques(const RobotModel& robot, const Eigen::Isometry3d& base_W, const JointVector& q,
                                   const std::vector<StanceFoot>& feet, const Eigen::Vector3d& com_W,
                                   const ForceDistributionParams& params, const Eigen::Vector3d& com_acceleration_W) {
  StanceTorques out;
  const double weight_N = robot.TotalMass() * kGravity;
  // The feet carry the weight and accelerate the CoM.
  Wrench load = Wrench::Zero();
  load.head<3>() = robot.TotalMass() * (com_acceleration_W + Eigen::Vector3d(0, 0, kGravity));
  out.forces = DistributeWrench(feet, com_W, load, params);
  const Wrench residual = out.forces.achieved - load;
  out.balanced = !feet.empty() && residual.head<3>().norm() <= 0.02 * weight_N &&
                 residual.tail<3>().norm() <= 0.02 * weight_N * 0.1;
  const Eigen::Matrix3d R_BW = base_W.linear().transpose();
  const Eigen::Vector3d gravity_B = R_BW * Eigen::Vector3d(0, 0, -kGravity);
  for (const StanceFoot& foot : feet) {
    const Eigen::Vector3d q_leg = LegJoints(q, foot.leg);
    const Eigen::Vector3d f_B = R_BW * out.forces.forces_W[static_cast<std::size_t>(Index(foot.leg))];
    const Eigen::Vector3d tau = robot.LegGravityTorques(foot.leg, q_leg, gravity_B) + robot.StaticTorques(foot.leg, q_leg, f_B);
    SetLegJoints(out.tau, foot.leg, tau);
    for (int j = 0; j < kJointsPerLeg; ++j) {
      if (std::abs(tau[j]) > out.max_abs_Nm || out.worst_joint < 0) {
        out.max_abs_Nm = std::abs(tau[j]);
        out.worst_joint = kJointsPerLeg * Index(foot.leg) + j;
      }
    }
  }
  return out;
}

}  // namespace rbcp
