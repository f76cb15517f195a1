#include "nnls.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>

namespace rbcp::detail {
namespace {

/// Storage of the solver's vectors and matrices: on the stack up to kMaxUnknowns columns.
template <int MaxN>
struct Storage {
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, MaxN, MaxN>;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, MaxN, 1>;
  using Flags = Eigen::Matrix<bool, Eigen::Dynamic, 1, 0, MaxN, 1>;
  using Indices = Eigen::Matrix<Eigen::Index, Eigen::Dynamic, 1, 0, MaxN, 1>;
};

/// The least-squares solution on the columns in `passive`, zero elsewhere: the normal equations
/// (AtA, Atb precomputed) restricted to those columns, by LDLT; by QR of those columns of A when
/// they are too close to dependent for the normal equations.
template <int MaxN>
typename Storage<MaxN>::Vector SolveOnSet(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                          const typename Storage<MaxN>::Matrix& AtA,
                                          const typename Storage<MaxN>::Vector& Atb,
                                          const typename Storage<MaxN>::Flags& passive) {
  using Matrix = typename Storage<MaxN>::Matrix;
  using Vector = typename Storage<MaxN>::Vector;
  typename Storage<MaxN>::Indices cols(A.cols());
  Eigen::Index k = 0;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    if (passive[j]) cols[k++] = j;
  }
  Matrix N(k, k);
  Vector r(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    r[i] = Atb[cols[i]];
    for (Eigen::Index j = 0; j < k; ++j) N(i, j) = AtA(cols[i], cols[j]);
  }
  const Eigen::LDLT<Matrix> ldlt(N);
  Vector zp;
  const double smallest = ldlt.vectorD().cwiseAbs().minCoeff();
  const double largest = ldlt.vectorD().cwiseAbs().maxCoeff();
  if (ldlt.info() == Eigen::Success && ldlt.isPositive() && smallest > 1e-12 * std::max(1.0, largest)) {
    zp = ldlt.solve(r);
  } else {
    Eigen::MatrixXd Ap(A.rows(), k);
    for (Eigen::Index i = 0; i < k; ++i) Ap.col(i) = A.col(cols[i]);
    zp = Ap.colPivHouseholderQr().solve(b);
  }
  Vector z = Vector::Zero(A.cols());
  for (Eigen::Index i = 0; i < k; ++i) z[cols[i]] = zp[i];
  return z;
}

template <int MaxN>
Eigen::VectorXd Solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  using Matrix = typename Storage<MaxN>::Matrix;
  using Vector = typename Storage<MaxN>::Vector;
  using Flags = typename Storage<MaxN>::Flags;
  const Eigen::Index n = A.cols();
  const Matrix AtA = A.transpose() * A;
  const Vector Atb = A.transpose() * b;
  Vector x = Vector::Zero(n);
  Flags passive = Flags::Constant(n, false);
  const double tol = 1e-10 * std::max(1.0, A.norm() * b.norm());
  for (int outer = 0; outer < 3 * n; ++outer) {
    const Vector w = Atb - AtA * x;  // A^T (b - A x)
    Eigen::Index best = -1;
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!passive[j] && w[j] > tol && (best < 0 || w[j] > w[best])) best = j;
    }
    if (best < 0) break;
    passive[best] = true;
    for (int inner = 0; inner < 3 * n; ++inner) {
      const Vector z = SolveOnSet<MaxN>(A, b, AtA, Atb, passive);
      bool all_positive = true;
      double alpha = 1.0;
      for (Eigen::Index j = 0; j < n; ++j) {
        if (passive[j] && z[j] <= 0.0) {
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
        if (passive[j] && x[j] <= tol) {
          passive[j] = false;
          x[j] = 0.0;
        }
      }
    }
  }
  return x.cwiseMax(0.0);
}

}  // namespace

Eigen::VectorXd SolveNnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  // The force distribution's problems (at most 16 unknowns) without a heap allocation per step.
  constexpr int kMaxUnknowns = 16;
  return A.cols() <= kMaxUnknowns ? Solve<kMaxUnknowns>(A, b) : Solve<Eigen::Dynamic>(A, b);
}

}  // namespace rbcp::detail
