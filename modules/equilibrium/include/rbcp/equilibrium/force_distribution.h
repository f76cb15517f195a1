#pragma once
/// Distribution of a desired trunk wrench onto the stance feet, with every force inside its
/// linearised friction cone: min ||W (A f - w)||^2 + regularisation, f_i = G_i lambda_i,
/// lambda_i >= lambda_min,i (a least normal force), solved as non-negative least squares.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "rbcp/core/leg.h"

namespace rbcp {

using Wrench = Eigen::Matrix<double, 6, 1>;  ///< (force [N], torque [N m]), world frame

/// A foot that may push on the terrain.
struct StanceFoot {
  Leg leg = Leg::kLF;
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();  ///< contact point [m]
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();   ///< surface normal, unit
  /// Share of a full stance foot's load in (0, 1]: a leg being unloaded or reloaded carries less
  /// (its least normal force scales with it and its regularisation grows as 1 / load^2).
  double load = 1.0;
};

struct ForceDistributionParams {
  double friction = 0.5;             ///< [-]
  double min_normal_force_N = 10.0;  ///< of a fully loaded foot [N]
  /// Residual weights of (force x, y, z, torque x, y, z).
  Wrench weights = (Wrench() << 1.0, 1.0, 1.0, 10.0, 10.0, 5.0).finished();
  double regularisation = 1e-4;      ///< weight of sum ||lambda||^2
};

struct ForceDistribution {
  /// Force the terrain exerts on each foot [N], world frame, by Index(Leg); zero off stance.
  std::array<Eigen::Vector3d, kNumLegs> forces_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                                 Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  Wrench achieved = Wrench::Zero();  ///< wrench of the forces about the point given [N, N m]
};

/// Forces on `feet` whose wrench about `point_W` (usually the CoM) comes closest to `wrench_W`.
ForceDistribution DistributeWrench(const std::vector<StanceFoot>& feet, const Eigen::Vector3d& point_W,
                                   const Wrench& wrench_W, const ForceDistributionParams& params);

}  // namespace rbcp
