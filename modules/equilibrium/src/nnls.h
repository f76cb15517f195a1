#pragma once
// Non-negative least squares, min ||A x - b|| subject to x >= 0 (Lawson and Hanson's active-set
// method, its subproblems solved on the normal equations). Small dense problems only: the force
// distribution has at most 16 unknowns.

#include <Eigen/Core>

namespace rbcp::detail {

/// The solution x >= 0. Deterministic; at most 3 * cols outer iterations.
Eigen::VectorXd SolveNnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b);

}  // namespace rbcp::detail
