#include "rbcp/stance/zmp_preview.h"

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

using Matrix4d = Eigen::Matrix4d;
using Vector4d = Eigen::Vector4d;

constexpr int kMaxRiccatiIterations = 200000;
constexpr double kRiccatiTolerance = 1e-11;  // relative change of P per iteration
constexpr int kMaxTailSteps = 1000000;        // preview samples summed beyond the window, at most
constexpr double kTailTolerance = 1e-14;      // a tail gain this small against the first ends the sum

/// The solution P of the discrete algebraic Riccati equation of (a, b, q, r), by its recursion.
Matrix4d SolveRiccati(const Matrix4d& a, const Vector4d& b, const Matrix4d& q, double r) {
  Matrix4d p = q;
  for (int i = 0; i < kMaxRiccatiIterations; ++i) {
    const double s = r + b.dot(p * b);
    const Eigen::RowVector4d k = (b.transpose() * p * a) / s;
    const Matrix4d next = q + a.transpose() * p * a - a.transpose() * p * b * k;
    const double change = (next - p).norm();
    p = next;
    if (change <= kRiccatiTolerance * std::max(1.0, p.norm())) return p;
  }
  throw InputError("ZMP preview: the Riccati recursion did not converge in " + std::to_string(kMaxRiccatiIterations) +
                   " iterations");
}

}  // namespace

ZmpPreviewModel::ZmpPreviewModel(const ZmpPreviewParams& params) : params_(params) {
  const ZmpPreviewParams& p = params;
  p.Validate("ZMP preview");

  const double t = p.time_step_s;
  a_ << 1.0, t, t * t / 2.0, 0.0, 1.0, t, 0.0, 0.0, 1.0;
  b_ << t * t * t / 6.0, t * t / 2.0, t;
  c_ << 1.0, 0.0, -p.com_height_m / p.gravity_mps2;

  // The system augmented with the ZMP error (Katayama et al. 1985): state (e, dx), input du.
  Matrix4d a_aug = Matrix4d::Zero();
  a_aug(0, 0) = 1.0;
  a_aug.block<1, 3>(0, 1) = c_ * a_;
  a_aug.block<3, 3>(1, 1) = a_;
  Vector4d b_aug;
  b_aug(0) = c_.dot(b_);
  b_aug.tail<3>() = b_;
  Matrix4d q_aug = Matrix4d::Zero();
  q_aug(0, 0) = p.q_error;

  const Matrix4d riccati = SolveRiccati(a_aug, b_aug, q_aug, p.r_jerk);
  const double s = p.r_jerk + b_aug.dot(riccati * b_aug);
  const Eigen::RowVector4d k = (b_aug.transpose() * riccati * a_aug) / s;
  integral_gain_ = k(0);
  state_gain_ = k.tail<3>();

  // Preview gains: G(1) = -Gi, G(j + 1) = s^-1 b' X_j with X_1 = -Ac' P e1, X_{j+1} = Ac' X_j.
  const int steps = static_cast<int>(std::lround(p.preview_s / p.time_step_s));
  const Matrix4d closed_loop = a_aug - b_aug * k;
  Vector4d x = -closed_loop.transpose() * riccati * Vector4d::UnitX();
  preview_gains_.resize(static_cast<std::size_t>(steps));
  preview_gains_[0] = -integral_gain_;
  for (int j = 1; j < steps; ++j) {
    preview_gains_[static_cast<std::size_t>(j)] = b_aug.dot(x) / s;
    x = closed_loop.transpose() * x;
  }
  // Beyond the window the reference is held at its last previewed sample (PreviewCom does so), so
  // the gains of the samples beyond it add to the last one: a constant reference is then held
  // without the drift a truncated sum leaves to the integral term.
  if (steps > 1) {
    for (int j = steps; j < kMaxTailSteps && x.norm() > 0.0; ++j) {
      const double gain = b_aug.dot(x) / s;
      preview_gains_.back() += gain;
      if (std::abs(gain) < kTailTolerance * std::abs(preview_gains_.front())) break;
      x = closed_loop.transpose() * x;
    }
  }
}

ComTrajectory PreviewCom(const ZmpPreviewModel& model, const Eigen::Vector2d& start,
                         const std::vector<Eigen::Vector2d>& zmp_reference) {
  ComState rest;
  rest.position = start;
  return PreviewCom(model, rest, zmp_reference);
}

namespace {

void CheckPreviewInput(const ComState& start, const std::vector<Eigen::Vector2d>& zmp_reference) {
  if (zmp_reference.empty()) throw InputError("ZMP preview: expected a reference of at least one sample, got none");
  if (!start.position.allFinite() || !start.velocity.allFinite() || !start.acceleration.allFinite() ||
      !start.zmp_error_sum.allFinite()) {
    throw InputError("ZMP preview: expected a finite start");
  }
  for (std::size_t k = 0; k < zmp_reference.size(); ++k) {
    if (!zmp_reference[k].allFinite()) {
      throw InputError("ZMP preview: reference sample " + std::to_string(k) + " is not finite");
    }
  }
}

/// `jerk` less the preview's share at sample k along `axis`, sum_j G_j p_ref[k + 1 + j].
double LessPreview(double jerk, const ZmpPreviewModel& model, const std::vector<Eigen::Vector2d>& zmp_reference,
                   std::size_t k, int axis) {
  const std::vector<double>& preview = model.PreviewGains();
  const std::size_t n = zmp_reference.size();
  for (std::size_t j = 0; j < preview.size(); ++j) jerk -= preview[j] * zmp_reference[std::min(k + 1 + j, n - 1)][axis];
  return jerk;
}

}  // namespace

Eigen::Vector2d ZmpErrorSumForJerk(const ZmpPreviewModel& model, const ComState& start,
                                   const std::vector<Eigen::Vector2d>& zmp_reference, const Eigen::Vector2d& jerk) {
  CheckPreviewInput(start, zmp_reference);
  if (!jerk.allFinite()) throw InputError("ZMP preview: expected a finite jerk");
  Eigen::Vector2d sum;
  for (int axis = 0; axis < 2; ++axis) {
    const Eigen::Vector3d x(start.position[axis], start.velocity[axis], start.acceleration[axis]);
    // PreviewCom's first jerk, -Ki (sum + e0) - Kx x + preview, solved for the sum.
    const double e0 = model.C() * x - zmp_reference[0][axis];
    const double rest = LessPreview(-model.StateGain() * x, model, zmp_reference, 0, axis);
    sum[axis] = (rest - jerk[axis]) / model.IntegralGain() - e0;
  }
  return sum;
}

ComTrajectory PreviewCom(const ZmpPreviewModel& model, const ComState& start,
                         const std::vector<Eigen::Vector2d>& zmp_reference) {
  CheckPreviewInput(start, zmp_reference);
  const std::size_t n = zmp_reference.size();
  ComTrajectory out;
  out.position.resize(n);
  out.velocity.resize(n);
  out.acceleration.resize(n);
  out.zmp.resize(n);
  out.zmp_error_sum.resize(n);
  for (int axis = 0; axis < 2; ++axis) {
    Eigen::Vector3d x(start.position[axis], start.velocity[axis], start.acceleration[axis]);
    double error_sum = start.zmp_error_sum[axis];
    for (std::size_t k = 0; k < n; ++k) {
      const double zmp = model.C() * x;
      out.position[k][axis] = x[0];
      out.velocity[k][axis] = x[1];
      out.acceleration[k][axis] = x[2];
      out.zmp[k][axis] = zmp;
      out.zmp_error_sum[k][axis] = error_sum;
      error_sum += zmp - zmp_reference[k][axis];
      const double jerk =
          LessPreview(-model.IntegralGain() * error_sum - model.StateGain() * x, model, zmp_reference, k, axis);
      x = model.A() * x + model.B() * jerk;
    }
  }
  return out;
}

}  // namespace rbcp
