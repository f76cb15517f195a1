#include "nnls.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <vector>

namespace rbcp::detail {
namespace {

/// The least-squares solution on the columns in `passive`, zero elsewhere: the normal equations
/// (AtA, Atb precomputed) restricted to those columns, by LDLT; by QR of those columns of A when
/// they are too close to dependent for the normal equations.
Eigen::VectorXd SolveOnSet(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::MatrixXd& AtA,
                           const Eigen::VectorXd& Atb, const std::vector<bool>& passive) {
  std::vector<Eigen::Index> cols;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    if (passive[static_cast<std::size_t>(j)]) cols.push_back(j);
  }
  const auto k = static_cast<Eigen::Index>(cols.size());
  Eigen::MatrixXd N(k, k);
  Eigen::VectorXd r(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    r[i] = Atb[cols[static_cast<std::size_t>(i)]];
    for (Eigen::Index j = 0; j < k; ++j) N(i, j) = AtA(cols[static_cast<std::size_t>(i)], cols[static_cast<std::size_t>(j)]);
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(N);
  Eigen::VectorXd zp;
  const double smallest = ldlt.vectorD().cwiseAbs().minCoeff();
  const double largest = ldlt.vectorD().cwiseAbs().maxCoeff();
  if (ldlt.info() == Eigen::Success && ldlt.isPositive() && smallest > 1e-12 * std::max(1.0, largest)) {
    zp = ldlt.solve(r);
  } else {
    Eigen::MatrixXd Ap(A.rows(), k);
    for (Eigen::Index i = 0; i < k; ++i) Ap.col(i) = A.col(cols[static_cast<std::size_t>(i)]);
    zp = Ap.colPivHouseholderQr().solve(b);
  }
  Eigen::VectorXd z = Eigen::VectorXd::Zero(A.cols());
  for (Eigen::Index i = 0; i < k; ++i) z[cols[static_cast<std::size_t>(i)]] = zp[i];
  return z;
}

}  // namespace

Eigen::VectorXd SolveNnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  const Eigen::Index n = A.cols();
  const Eigen::MatrixXd AtA = A.transpose() * A;
  const Eigen::VectorXd Atb = A.transpose() * b;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> passive(static_cast<std::size_t>(n), false);
  const double tol = 1e-10 * std::max(1.0, A.norm() * b.norm());
  for (int outer = 0; outer < 3 * n; ++outer) {
    const Eigen::VectorXd w = Atb - AtA * x;  // A^T (b - A x)
    Eigen::Index best = -1;
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!passive[static_cast<std::size_t>(j)] && w[j] > tol && (best < 0 || w[j] > w[best])) best = j;
    }
    if (best < 0) break;
    passive[static_cast<std::size_t>(best)] = true;
    for (int inner = 0; inner < 3 * n; ++inner) {
      const Eigen::VectorXd z = SolveOnSet(A, b, AtA, Atb, passive);
      bool all_positive = true;
      double alpha = 1.0;
      for (Eigen::Index j = 0; j < n; ++j) {
        if (passive[static_cast<std::size_t>(j)] && z[j] <= 0.0) {
          all_positive = false;
          const double denom = x[j] - z[j];
          if (denom > 0.0) alpha = std::min(alpha, x[j] / denom);
        }
      }
      if (all_positive) {
        x = z;
        break;
      }
      x += alpha * (z - x);
      for (Eigen::Index j = 0; j < n; ++j) {
        if (passive[static_cast<std::size_t>(j)] && x[j] <= tol) {
          passive[static_cast<std::size_t>(j)] = false;
          x[j] = 0.0;
        }
      }
    }
  }
  return x.cwiseMax(0.0);
}

}  // namespace rbcp::detail
