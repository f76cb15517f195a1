#include "rbcp/equilibrium/force_distribution.h"

#include <algorithm>
#include <cmath>

#include "nnls.h"
#include "rbcp/equilibrium/friction_cone.h"

namespace rbcp {
namespace {

constexpr int kGenerators = 4;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

}  // namespace

ForceDistribution DistributeWrench(const std::vector<StanceFoot>& feet, const Eigen::Vector3d& point_W,
                                   const Wrench& wrench_W, const ForceDistributionParams& params) {
  ForceDistribution out;
  if (feet.empty()) return out;
  const int n = kGenerators * static_cast<int>(feet.size());
  // Wrench of the generator weights: rows (force, torque about point_W).
  Eigen::MatrixXd M(6, n);
  Eigen::VectorXd lambda_min(n);
  Eigen::VectorXd reg(n);
  // Normal component of one generator: the generators are unit vectors at atan(mu) from n.
  const double normal_per_generator = 1.0 / std::sqrt(1.0 + params.friction * params.friction);
  for (std::size_t i = 0; i < feet.size(); ++i) {
    const StanceFoot& foot = feet[i];
    const Eigen::Matrix3Xd G = FrictionConeGenerators(foot.normal_W, params.friction, kGenerators);
    const int c = kGenerators * static_cast<int>(i);
    M.block(0, c, 3, kGenerators) = G;
    M.block(3, c, 3, kGenerators) = Skew(foot.position_W - point_W) * G;
    const double load = std::clamp(foot.load, 1e-3, 1.0);
    lambda_min.segment(c, kGenerators).setConstant(load * params.min_normal_force_N /
                                                   (kGenerators * normal_per_generator));
    reg.segment(c, kGenerators).setConstant(params.regularisation / (load * load));
  }
  // lambda = lambda_min + x, x >= 0:  min ||S (M x - (w - M lambda_min))||^2 + ||sqrt(reg) (x + lambda_min)||^2.
  const Wrench sqrt_w = params.weights.cwiseSqrt();
  Eigen::MatrixXd A(6 + n, n);
  Eigen::VectorXd b(6 + n);
  A.topRows(6) = sqrt_w.asDiagonal() * M;
  b.head(6) = sqrt_w.cwiseProduct(wrench_W - M * lambda_min);
  A.bottomRows(n) = reg.cwiseSqrt().asDiagonal();
  b.tail(n) = -reg.cwiseSqrt().cwiseProduct(lambda_min);
  const Eigen::VectorXd lambda = lambda_min + detail::SolveNnls(A, b);
  for (std::size_t i = 0; i < feet.size(); ++i) {
    const int c = kGenerators * static_cast<int>(i);
    out.forces_W[static_cast<std::size_t>(Index(feet[i].leg))] =
        M.block(0, c, 3, kGenerators) * lambda.segment(c, kGenerators);
  }
  out.achieved = M * lambda;
  return out;
}

}  // namespace rbcp
