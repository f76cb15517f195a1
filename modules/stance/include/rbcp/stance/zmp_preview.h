#pragma once
/// ZMP preview control of a linear inverted pendulum (Kajita et al., "Biped walking pattern
/// generation by using preview control of zero-moment point", ICRA 2003): the CoM trajectory
/// whose zero-moment point follows a reference known some time ahead (the coming support
/// polygons of a contact plan). The CoM is a cart at constant height h driven by its jerk; its
/// ZMP is p = c - (h / g) c'' along each horizontal axis. The gains minimise
/// sum(q_error (p - p_ref)^2 + r_jerk (delta jerk)^2) over an infinite horizon (the discrete
/// algebraic Riccati equation, solved by its recursion in plain Eigen), with the reference
/// previewed over a finite window.
///
/// Pinocchio's pattern: `ZmpPreviewModel` is the constant model and its gains, computed once;
/// `ComTrajectory PreviewCom(model, ...)` is a free function of it.

#include <vector>

#include <Eigen/Core>

#include "rbcp/core/config_fields.h"

namespace rbcp {

/// The sampling and the cost of ZMP preview control: part of the dynamic walk's
/// configuration (DynamicWalkConfig); the pendulum's height comes with each plan.
struct ZmpPreviewSettings {
  double time_step_s = 0.0;
  double preview_s = 0.0;
  double q_error = 1.0;
  double r_jerk = 1e-6;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("time_step_s", &time_step_s, "s", bounds::Positive().AtMost(0.1), "sampling period of the CoM trajectory");
    v->Visit("preview_s", &preview_s, "s", Bounds().AtLeast(time_step_s, "time_step_s").AtMost(10.0),
             "how far ahead the ZMP preview looks");
    v->Visit("q_error", &q_error, "1/m^2", bounds::Positive(), "preview cost: weight of the ZMP error");
    v->Visit("r_jerk", &r_jerk, "s^6/m^2", bounds::Positive(), "preview cost: weight of the change of jerk");
  }
};

/// The pendulum, the sampling and the cost of ZMP preview control.
struct ZmpPreviewParams : ZmpPreviewSettings {
  double com_height_m = 0.0;
  double gravity_mps2 = 9.81;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("com_height_m", &com_height_m, "m", bounds::Positive(), "CoM height above the ZMP's plane");
    v->Visit("gravity_mps2", &gravity_mps2, "m/s^2", bounds::Positive(), "gravity");
    ZmpPreviewSettings::Serialize(v);
  }
  /// Throws InputError for a field outside its bounds.
  void Validate(const std::string& where = "ZmpPreviewParams") const { ValidateConfig(*this, where); }
};

/// The discrete cart-table model of one horizontal axis and its preview gains. Immutable.
class ZmpPreviewModel {
 public:
  /// Throws InputError for parameters outside their bounds, or when the Riccati recursion does not
  /// converge (it does for every valid set).
  explicit ZmpPreviewModel(const ZmpPreviewParams& params);

  const ZmpPreviewParams& Params() const { return params_; }
  /// State (c, c', c'') to the next: x+ = A x + B u, u the jerk over one period.
  const Eigen::Matrix3d& A() const { return a_; }
  const Eigen::Vector3d& B() const { return b_; }
  /// ZMP of a state: p = C x = c - (h / g) c''.
  const Eigen::RowVector3d& C() const { return c_; }
  /// u = -integral_gain * sum(p - p_ref) - state_gain * x - sum_j preview_gains[j] * p_ref[k + 1 + j].
  /// The last preview gain includes those of every sample beyond the window: the reference is
  /// taken as held there.
  double IntegralGain() const { return integral_gain_; }
  const Eigen::RowVector3d& StateGain() const { return state_gain_; }
  const std::vector<double>& PreviewGains() const { return preview_gains_; }
  /// Number of reference samples previewed beyond the current one: round(preview_s / time_step_s).
  int PreviewSteps() const { return static_cast<int>(preview_gains_.size()); }

 private:
  ZmpPreviewParams params_;
  Eigen::Matrix3d a_;
  Eigen::Vector3d b_;
  Eigen::RowVector3d c_;
  double integral_gain_ = 0.0;
  Eigen::RowVector3d state_gain_;
  std::vector<double> preview_gains_;
};

/// A horizontal CoM trajectory sampled every time step: position, velocity, acceleration, the
/// ZMP it implies and the preview controller's integral of the ZMP's tracking error, per sample
/// (x, y).
struct ComTrajectory {
  std::vector<Eigen::Vector2d> position;
  std::vector<Eigen::Vector2d> velocity;
  std::vector<Eigen::Vector2d> acceleration;
  std::vector<Eigen::Vector2d> zmp;
  std::vector<Eigen::Vector2d> zmp_error_sum;
};

/// The horizontal state of the CoM [m, m/s, m/s^2], with the preview controller's integral of the
/// ZMP's tracking error [m, summed over samples]. The integral is part of the controller's state:
/// a trajectory that goes on from a moving CoM must start from it too, or its first jerk differs
/// by the integral gain times the sum dropped (several m/s^2 of acceleration within 10 ms).
struct ComState {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
  Eigen::Vector2d acceleration = Eigen::Vector2d::Zero();
  Eigen::Vector2d zmp_error_sum = Eigen::Vector2d::Zero();
};

/// The CoM trajectory from `start` whose ZMP follows `zmp_reference` (one sample per time step;
/// beyond its end the last sample is held): one sample per reference sample, the first the start.
/// A walking robot's next piece of plan starts from the CoM as it moves; its reference must then
/// go on from the ZMP the CoM is following: a reference that ignores the motion is met by a ZMP
/// that stops the CoM at once, far outside any support. Throws InputError for an empty or
/// non-finite reference or start.
ComTrajectory PreviewCom(const ZmpPreviewModel& model, const ComState& start,
                         const std::vector<Eigen::Vector2d>& zmp_reference);
/// The integral of the ZMP error with which PreviewCom's first jerk from `start` (its own integral
/// aside) on `zmp_reference` is `jerk` [m/s^3]: a CoM whose motion the reference takes up as it
/// is, with no step of its jerk. Throws InputError as PreviewCom does.
Eigen::Vector2d ZmpErrorSumForJerk(const ZmpPreviewModel& model, const ComState& start,
                                   const std::vector<Eigen::Vector2d>& zmp_reference, const Eigen::Vector2d& jerk);
/// The same from rest at `start`.
ComTrajectory PreviewCom(const ZmpPreviewModel& model, const Eigen::Vector2d& start,
                         const std::vector<Eigen::Vector2d>& zmp_reference);

}  // namespace rbcp
