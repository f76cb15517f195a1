#include "nnls.h"

#include <gtest/gtest.h>

#include <random>

namespace rbcp::detail {
namespace {

TEST(Nnls, UnconstrainedOptimumWhenItIsNonNegative) {
  Eigen::MatrixXd A(3, 2);
  A << 1, 0, 0, 1, 1, 1;
  const Eigen::VectorXd x_true = Eigen::Vector2d(2.0, 3.0);
  const Eigen::VectorXd x = SolveNnls(A, A * x_true);
  EXPECT_NEAR((x - x_true).norm(), 0.0, 1e-10);
}

TEST(Nnls, ClampsAtZeroAndSatisfiesTheOptimalityConditions) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::MatrixXd A(8, 6);
    Eigen::VectorXd b(8);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = normal(rng);
    for (int i = 0; i < b.size(); ++i) b[i] = normal(rng);
    const Eigen::VectorXd x = SolveNnls(A, b);
    const Eigen::VectorXd w = A.transpose() * (b - A * x);  // minus the gradient
    for (int j = 0; j < x.size(); ++j) {
      EXPECT_GE(x[j], 0.0);
      if (x[j] > 1e-9) {
        EXPECT_NEAR(w[j], 0.0, 1e-8);  // free variables: zero gradient
      } else {
        EXPECT_LE(w[j], 1e-8);  // bound variables: the gradient pushes into the bound
      }
    }
  }
}

}  // namespace
}  // namespace rbcp::detail
