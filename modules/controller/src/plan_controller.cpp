#include "rbcp/controller/plan_controller.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/stance_torques.h"
#include "rbcp/equilibrium/static_equilibrium.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "rbcp/stance/dynamic_walk.h"

namespace rbcp {
namespace {

constexpr double kTouchdownHeightM = 0.02;  // [m] a contact this close above the foothold is a touchdown
constexpr double kTouchdownForceN = 5.0;  // [N] least contact force of a touchdown higher up
constexpr double kTouchdownCosine = 0.8;  // a touchdown force lies within 37 degrees of the normal (a
                                          // foot sliding down a riser face under friction 0.8: 52)

Eigen::Quaterniond QuaternionFromRpy(const Eigen::Vector3d& rpy) {
  return Eigen::Quaterniond(RotationFromRpy(rpy)).normalized();
}

/// Rotation vector of q (angle times axis), angle in [0, pi].
Eigen::Vector3d RotationVector(Eigen::Quaterniond q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Eigen::AngleAxisd aa(q);
  return aa.angle() * aa.axis();
}

}  // namespace

const char* ToString(ControllerPhase phase) {
  switch (phase) {
    case ControllerPhase::kHold: return "hold";
    case ControllerPhase::kSettle: return "settle";
    case ControllerPhase::kShift: return "shift";
    case ControllerPhase::kUnload: return "unload";
    case ControllerPhase::kSwing: return "swing";
    case ControllerPhase::kSearch: return "search";
    case ControllerPhase::kLoad: return "load";
    case ControllerPhase::kAwait: return "await";
    case ControllerPhase::kFinalShift: return "final_shift";
    case ControllerPhase::kDone: return "done";
    case ControllerPhase::kFailed: return "failed";
  }
  return "?";
}

/// The measured state in the forms the controller needs, computed once per tick.
struct PlanController::Measured {
  double t = 0.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // base to world
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_W = Eigen::Vector3d::Zero();
  JointVector q = JointVector::Zero();
  JointVector qd = JointVector::Zero();
  std::array<Eigen::Vector3d, kNumLegs> feet_W;
  std::array<bool, kNumLegs> contact{};
  std::array<Eigen::Vector3d, kNumLegs> force_W;
  Eigen::Vector3d com_W = Eigen::Vector3d::Zero();
};

namespace {

constexpr double kSameFootholdM = 0.02;  // [m] a foothold of a new plan this near the old one's is the same

/// Whether `next` (a plan from the stance after step `step` of `walked`) takes the step `walked`
/// takes next: the same leg to the same foothold. Past the last step there is none to miss.
bool GoesOn(const ContactPlan& walked, int step, const ContactPlan& next) {
  const std::size_t after = static_cast<std::size_t>(step) + 1;
  if (step < 0 || after >= walked.states.size() || next.states.size() < 2) return true;
  const WholeBodyState& planned = walked.states[after];
  const WholeBodyState& taken = next.states[1];
  if (planned.moving_leg != taken.moving_leg || taken.moving_leg < 0 || taken.moving_leg >= kNumLegs) return false;
  const std::size_t leg = static_cast<std::size_t>(taken.moving_leg);
  return (planned.feet[leg].position - taken.feet[leg].position).norm() <= kSameFootholdM;
}

}  // namespace

bool PlanController::OnFoothold(const Measured& m, std::size_t leg) const {
  // A touchdown is a contact at the foothold's height, or one that pushes along its normal (the
  // terrain is higher than planned). A foot that meets the terrain sideways above its foothold
  // (the face of a riser beside it) has not arrived: it goes on down.
  if (!m.contact[leg]) return false;
  const FootContact& planned = plan_.states[static_cast<std::size_t>(status_.step)].feet[leg];
  const Eigen::Vector3d n = planned.normal.normalized();
  if ((m.feet_W[leg] - planned.position).dot(n) <= kTouchdownHeightM) return true;
  const Eigen::Vector3d& f = m.force_W[leg];
  return f.norm() >= kTouchdownForceN && f.dot(n) >= kTouchdownCosine * f.norm();
}

PlanController::PlanController(const RobotModel& robot, const ControllerConfig& config, const StanceRules& rules,
                               const TriangleMesh* terrain)
    : robot_(robot), config_(config), stance_(robot, rules) {
  config_.Validate();
  normal_W_.fill(Eigen::Vector3d::UnitZ());
  touchdown_s_.fill(std::numeric_limits<double>::quiet_NaN());
  SetTerrain(terrain);
}

void PlanController::SetTerrain(const TriangleMesh* terrain) { stance_.SetTerrain(terrain); }

void PlanController::CheckPlan(const ContactPlan& plan) {
  if (plan.states.empty()) throw InputError("controller: expected a plan with at least one state, got none");
  for (std::size_t i = 0; i < plan.states.size(); ++i) {
    const WholeBodyState& s = plan.states[i];
    bool finite = s.base_position.allFinite() && s.base_rpy.allFinite() && s.joints.allFinite();
    for (const FootContact& f : s.feet) finite = finite && f.position.allFinite() && f.normal.allFinite();
    if (!finite) throw InputError("controller: plan state " + std::to_string(i) + ": expected finite numbers");
    for (const FootContact& f : s.feet) {
      if (f.normal.norm() < 0.5) {
        throw InputError("controller: plan state " + std::to_string(i) + ": expected unit foot normals, got |n| = " +
                         FixedNumber(f.normal.norm()));
      }
    }
    if (i > 0 && (s.moving_leg < 0 || s.moving_leg >= kNumLegs)) {
      throw InputError("controller: plan state " + std::to_string(i) + ": expected a moving leg in 0..3, got " +
                       std::to_string(s.moving_leg));
    }
  }
}

void PlanController::StartPlan(const ContactPlan& plan) {
  CheckPlan(plan);
  plan_ = plan;
  pending_.reset();
  plan_started_ = true;
}

void PlanController::ReplacePlan(const ContactPlan& plan) {
  CheckPlan(plan);
  const ControllerPhase ph = status_.phase;
  if (ph == ControllerPhase::kHold || ph == ControllerPhase::kSettle || ph == ControllerPhase::kDone ||
      ph == ControllerPhase::kFinalShift) {
    StartPlan(plan);
  } else {
    pending_ = plan;
  }
}

void PlanController::ContinuePlan() {
  if (status_.phase == ControllerPhase::kAwait) continue_requested_ = true;
}

void PlanController::Enter(ControllerPhase phase, double t) {
  status_.phase = phase;
  status_.phase_start_s = t;
}

void PlanController::MoveBaseTo(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double t, double min_duration) {
  const double distance = (p - reference_.position_W).norm();
  const double angle = reference_.orientation_W.angularDistance(q);
  // Min-jerk peaks at 1.875 times its mean speed: time it so the peak stays at the set speeds.
  MoveBaseOver(p, q, t,
               std::max({min_duration, 1.875 * distance / config_.base.speed_mps,
                         1.875 * angle / config_.base.yaw_rate_radps}));
}

void PlanController::MoveBaseOver(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double t, double duration) {
  BaseSegment s;
  s.t0 = t;
  s.p0 = reference_.position_W;
  s.q0 = reference_.orientation_W;
  s.p1 = p;
  s.q1 = q;
  if (s.q0.dot(s.q1) < 0.0) s.q1.coeffs() = -s.q1.coeffs();
  s.duration = std::max(duration, 1e-3);
  segment_ = s;
}

void PlanController::StartPattern(const Measured& m, bool come_to_rest) {
  PatternStart start;
  if (pattern_ && pattern_time_s_ < pattern_->Duration()) {
    start.com = pattern_->ComAt(pattern_time_s_);  // walking: go on from where the CoM is headed
    start.zmp = pattern_->ZmpReferenceAt(pattern_time_s_);
    // A foot down before its swing's end: the rest of the swing's time goes on.
    if (status_.step >= 1 && status_.step <= pattern_->Steps()) {
      start.hold_s = std::max(0.0, pattern_->SwingOf(status_.step).end_s - pattern_time_s_);
    }
    // Headed for a step the plan does not take: the CoM comes to rest as from a stand (the time
    // a walk from rest gives the ZMP to settle under it), and the plan is walked from there.
    if (come_to_rest) {
      start.come_to_rest = true;
      start.hold_s = std::max(start.hold_s, 0.5 * stance_.Config().dynamic_walk.gait.start_s);
    }
  } else {
    start.com.position = m.com_W.head<2>();
  }
  pattern_ = DynamicWalkPattern(stance_, plan_, start);
  pattern_time_s_ = 0.0;
}

int PlanController::CommittedSteps() const {
  if (!pattern_) return 0;
  const int last = static_cast<int>(plan_.states.size()) - 1;
  const bool between_steps = status_.step == 0 || status_.phase == ControllerPhase::kAwait;
  const int current = status_.step + (between_steps ? 1 : 0);
  if (current > last) return 0;
  const double horizon_s = pattern_->SwingOf(current).end_s + stance_.Config().dynamic_walk.preview.preview_s;
  int committed = 0;
  for (int i = current + 1; i <= last && pattern_->SwingOf(i).start_s < horizon_s; ++i) ++committed;
  return committed;
}

void PlanController::AdvanceClock(const Measured& m) {
  const double dt = std::max(0.0, m.t - last_tick_s_);
  clock_held_ = false;
  if (!pattern_) return;
  // The clock stops at the current step's swing end until the foot is down, and waiting for the
  // next piece of plan, at the next lift-off.
  double limit = pattern_->Duration();
  switch (status_.phase) {
    case ControllerPhase::kUnload:
      limit = pattern_->SwingOf(status_.step).start_s;  // until the leg is unloaded (AdvanceUnload)
      break;
    case ControllerPhase::kShift:
    case ControllerPhase::kSwing:
    case ControllerPhase::kSearch:
      limit = pattern_->SwingOf(status_.step).end_s;
      break;
    case ControllerPhase::kAwait:
      if (status_.step + 1 < static_cast<int>(plan_.states.size())) limit = pattern_->SwingOf(status_.step + 1).start_s;
      break;
    default:
      break;
  }
  const double next = std::min(pattern_time_s_ + dt, std::max(limit, pattern_time_s_));
  if (next < pattern_time_s_ + dt && pattern_time_s_ < pattern_->Duration()) {
    clock_held_ = true;
    status_.lag_s += pattern_time_s_ + dt - next;
  }
  pattern_time_s_ = next;
}

void PlanController::RampLoads(const Measured& m) {
  for (std::size_t i = 0; i < kNumLegs; ++i) {
    if (std::isnan(touchdown_s_[i])) continue;
    load_[i] = std::clamp((m.t - touchdown_s_[i]) / Ramps().load_s, 0.0, 1.0);
    if (load_[i] >= 1.0) touchdown_s_[i] = std::numeric_limits<double>::quiet_NaN();
  }
}

void PlanController::TakePendingPlan(const Measured& m) {
  const bool goes_on = GoesOn(plan_, status_.step, *pending_);
  plan_ = std::move(*pending_);
  pending_.reset();
  status_.plan_start_s = m.t;
  if (Dynamic() && plan_.states.size() > 1) StartPattern(m, !goes_on);
}

void PlanController::EvaluateReference(double t) {
  const BaseSegment& s = segment_;
  const double u = std::clamp((t - s.t0) / s.duration, 0.0, 1.0);
  const double x = MinJerk(u);
  const double xd = (u > 0.0 && u < 1.0) ? MinJerkRate(u) / s.duration : 0.0;
  reference_.position_W = s.p0 + x * (s.p1 - s.p0);
  reference_.linear_velocity_W = xd * (s.p1 - s.p0);
  reference_.orientation_W = s.q0.slerp(x, s.q1);
  reference_.angular_velocity_W = xd * RotationVector(s.q1 * s.q0.conjugate());
  reference_.linear_acceleration_W.setZero();
}

void PlanController::BeginStep(int index, const Measured& m) {
  const WholeBodyState& target = plan_.states[static_cast<std::size_t>(index)];
  status_.step = index;
  status_.swing_leg = static_cast<Leg>(target.moving_leg);
  status_.step_max_base_error_m = 0.0;
  if (Dynamic()) {
    // Height and attitude reach the step's pose by its lift-off, as the planner checked the
    // swing; the pattern moves the CoM.
    const double until_liftoff = pattern_->SwingOf(index).start_s - pattern_time_s_;
    MoveBaseOver(target.base_position, QuaternionFromRpy(target.base_rpy), m.t, until_liftoff);
  } else {
    // The plan's base pose is the one the planner checked the step at: the base goes exactly there.
    MoveBaseTo(target.base_position, QuaternionFromRpy(target.base_rpy), m.t, config_.base.min_shift_s);
  }
  Enter(ControllerPhase::kShift, m.t);
}

SwingTrajectory PlanController::PlanSwing(int index, const Eigen::Vector3d& foot_W) const {
  // The path the planner checked: from the previous state's foothold to the new one, the base at
  // the step's pose, started where the foot really is (a few millimetres off, at most). A plan
  // that carries no swing is walked on the path the stance rules plan from the same footholds.
  if (Dynamic()) return DynamicSwing(stance_, plan_, index, foot_W);
  const WholeBodyState& target = plan_.states[static_cast<std::size_t>(index)];
  const std::size_t i = static_cast<std::size_t>(target.moving_leg);
  if (target.HasSwing()) {
    return SwingTrajectory::Given(foot_W, target.feet[i].position, target.swing_apex_z, target.swing_bow, stance_.Config().swing);
  }
  const WholeBodyState& before = plan_.states[static_cast<std::size_t>(index - 1)];
  const SwingTrajectory planned = stance_.PlanSwing(static_cast<Leg>(target.moving_leg), before.feet[i].position,
                                                    target.feet[i].position, BasePose(target), target.joints);
  return planned.StartingAt(foot_W);
}

void PlanController::FinishStep(const Measured& m) {
  status_.steps_done += 1;
  status_.swing_leg.reset();
  if (await_plans_) {
    const bool last = status_.step + 1 >= static_cast<int>(plan_.states.size());
    if (last && plan_.reaches_goal && !pending_) {
      BeginFinalShift(m);
    } else {
      continue_requested_ = false;
      Enter(ControllerPhase::kAwait, m.t);
    }
    return;
  }
  if (pending_) {
    TakePendingPlan(m);
    if (plan_.states.size() > 1) {
      BeginStep(1, m);
      return;
    }
  } else if (status_.step + 1 < static_cast<int>(plan_.states.size())) {
    BeginStep(status_.step + 1, m);
    return;
  }
  BeginFinalShift(m);
}

void PlanController::NextStepOrFinish(const Measured& m) {
  if (status_.step + 1 < static_cast<int>(plan_.states.size())) {
    BeginStep(status_.step + 1, m);
  } else if (plan_.reaches_goal) {
    BeginFinalShift(m);
  } else {
    Enter(ControllerPhase::kAwait, m.t);  // nothing left to walk: hold the stance
  }
}

void PlanController::BeginFinalShift(const Measured& m) {
  const WholeBodyState& last = plan_.states.back();
  if (pattern_) {
    MoveBaseOver(last.base_position, QuaternionFromRpy(last.base_rpy), m.t, pattern_->Duration() - pattern_time_s_);
  } else {
    MoveBaseTo(last.base_position, QuaternionFromRpy(last.base_rpy), m.t, config_.base.min_shift_s);
  }
  Enter(ControllerPhase::kFinalShift, m.t);
}

void PlanController::Fail(const Measured& m, Leg leg, const std::string& why) {
  status_.failure = why;
  status_.failure_leg = leg;
  // Hold the base where it is now, on the feet that are down.
  pattern_.reset();
  MoveBaseTo(reference_.position_W, reference_.orientation_W, m.t, config_.base.min_shift_s);
  Enter(ControllerPhase::kFailed, m.t);
}

void PlanController::BeginPlan(const Measured& m) {
  plan_started_ = false;
  status_ = ControllerStatus{};
  status_.plan_start_s = m.t;
  load_.fill(1.0);
  touchdown_s_.fill(std::numeric_limits<double>::quiet_NaN());
  for (Leg leg : kAllLegs) normal_W_[static_cast<std::size_t>(Index(leg))] = plan_.states.front().feet[static_cast<std::size_t>(Index(leg))].normal.normalized();
  const WholeBodyState& first = plan_.states.front();
  if (Dynamic() && plan_.states.size() > 1) {
    StartPattern(m);
    BeginStep(1, m);
    return;
  }
  pattern_.reset();
  MoveBaseTo(first.base_position, QuaternionFromRpy(first.base_rpy), m.t, config_.base.settle_s);
  Enter(ControllerPhase::kSettle, m.t);
}

void PlanController::Advance(const Measured& m) {
  if (plan_started_) BeginPlan(m);
  if (Dynamic()) {
    AdvanceClock(m);
    RampLoads(m);
  }
  // Phases may end within one tick; a few transitions at most follow each other.
  for (int guard = 0; guard < 4; ++guard) {
    const ControllerPhase before = status_.phase;
    AdvancePhase(m);
    if (status_.phase == before) break;
  }
}

void PlanController::AdvancePhase(const Measured& m) {
  const double t = m.t;
  const double elapsed = t - status_.phase_start_s;
  const std::size_t sl = status_.swing_leg ? static_cast<std::size_t>(Index(*status_.swing_leg)) : 0;
  switch (status_.phase) {
    case ControllerPhase::kHold:
    case ControllerPhase::kDone:
    case ControllerPhase::kFailed:
      break;
    case ControllerPhase::kSettle:
      if (segment_.Done(t)) {
        if (plan_.states.size() > 1) {
          BeginStep(1, m);
        } else {
          Enter(ControllerPhase::kFinalShift, t);
        }
      }
      break;
    case ControllerPhase::kShift:
      if (pattern_ ? pattern_time_s_ >= pattern_->SwingOf(status_.step).start_s - Ramps().unload_s
                   : segment_.Done(t)) {
        Enter(ControllerPhase::kUnload, t);
        unload_began_s_ = t;
      }
      break;
    case ControllerPhase::kUnload: AdvanceUnload(m, sl, elapsed); break;
    case ControllerPhase::kSwing: AdvanceSwing(m, sl); break;
    case ControllerPhase::kSearch: AdvanceSearch(m, sl, elapsed); break;
    case ControllerPhase::kLoad:
      if (pattern_) {
        FinishStep(m);  // the leg loads while the walk goes on (RampLoads)
        break;
      }
      load_[sl] = std::clamp(elapsed / Ramps().load_s, 0.0, 1.0);
      if (elapsed >= Ramps().load_s) {
        load_[sl] = 1.0;
        FinishStep(m);
      }
      break;
    case ControllerPhase::kAwait: AdvanceAwait(m); break;
    case ControllerPhase::kFinalShift:
      if (pattern_ ? pattern_time_s_ >= pattern_->Duration()
                   : segment_.Done(t) && elapsed >= segment_.duration + config_.base.final_hold_s) {
        Enter(ControllerPhase::kDone, t);
      }
      break;
  }
}

void PlanController::AdvanceUnload(const Measured& m, std::size_t sl, double elapsed) {
  touchdown_s_[sl] = std::numeric_limits<double>::quiet_NaN();  // a leg that steps again unloads from here
  load_[sl] = std::clamp(1.0 - elapsed / Ramps().unload_s, 0.0, 1.0);
  if (elapsed < Ramps().unload_s) return;
  // The leg lifts when the other three feet carry the robot: the centre of pressure of the feet's
  // measured forces inside their triangle. A trunk leaning over the leg (a push) makes it take its
  // load again and unload anew, the walk's clock waiting, for a while.
  constexpr double kLiftOffWaitS = 0.5;
  if (Dynamic() && m.t - unload_began_s_ < Ramps().unload_s + kLiftOffWaitS && !CarriedWithout(m, sl)) {
    load_[sl] = 1.0;
    status_.phase_start_s = m.t;
    return;
  }
  load_[sl] = 0.0;
  status_.stance[sl] = false;
  swing_ = PlanSwing(status_.step, m.feet_W[sl]);
  swing_q_des_ = LegJoints(m.q, static_cast<Leg>(sl));
  swing_hurried_at_.reset();
  tipping_since_.reset();
  Enter(ControllerPhase::kSwing, m.t);
}

CentreOfPressure PlanController::StanceCentreOfPressure(const Measured& m) const {
  std::vector<Eigen::Vector3d> feet;
  std::vector<double> normal_N;
  for (std::size_t i = 0; i < kNumLegs; ++i) {
    if (!status_.stance[i]) continue;
    feet.push_back(m.feet_W[i]);
    normal_N.push_back(m.force_W[i].dot(normal_W_[i]));
  }
  return ComputeCentreOfPressure(feet, normal_N);
}

bool PlanController::Tipping(const Measured& m) const {
  return StanceCentreOfPressure(m).margin_m < config_.swing.tip_margin_m;  // false when NaN (no three feet pushing)
}

bool PlanController::CarriedWithout(const Measured& m, std::size_t leg) const {
  std::vector<Eigen::Vector3d> others;
  for (std::size_t i = 0; i < kNumLegs; ++i) {
    if (status_.stance[i] && i != leg) others.push_back(m.feet_W[i]);
  }
  const CentreOfPressure cop = StanceCentreOfPressure(m);
  if (!cop.position.allFinite() || others.size() < 3) return true;  // nothing to go by
  return SupportPolygonMargin(others, cop.position) >= config_.swing.tip_margin_m;
}

double PlanController::SwingTime(double t) const {
  const double elapsed = t - status_.phase_start_s;
  if (!swing_hurried_at_) return elapsed;
  const double before = *swing_hurried_at_ - status_.phase_start_s;
  return before + config_.swing.tip_speedup * (elapsed - before);
}

void PlanController::AdvanceSwing(const Measured& m, std::size_t sl) {
  if (!swing_hurried_at_) {
    if (!Tipping(m)) {
      tipping_since_.reset();
    } else if (!tipping_since_) {
      tipping_since_ = m.t;
    }
    if (tipping_since_ && m.t - *tipping_since_ >= config_.swing.tip_hold_s) {
      swing_hurried_at_ = m.t;
      status_.hurried_swings += 1;
    }
  }
  const double elapsed = SwingTime(m.t);
  const double phase = swing_.Phase(elapsed);
  if (OnFoothold(m, sl) && phase >= config_.swing.touchdown_phase) {
    if (phase < 1.0) status_.early_touchdowns += 1;
    TouchDown(sl, m.t);
  } else if (elapsed >= swing_.Duration()) {
    status_.late_touchdowns += 1;
    search_start_W_ = swing_.Position(swing_.Duration());
    Enter(ControllerPhase::kSearch, m.t);
  }
}

void PlanController::AdvanceSearch(const Measured& m, std::size_t sl, double elapsed) {
  if (OnFoothold(m, sl)) {
    TouchDown(sl, m.t);
  } else if (elapsed * config_.swing.search_speed_mps >= config_.swing.search_depth_m) {
    Fail(m, static_cast<Leg>(sl),
         std::string(LegName(static_cast<Leg>(sl))) + " found no ground within " +
             FixedNumber(config_.swing.search_depth_m + stance_.Config().swing.touchdown_depth_m) +
             " m below its foothold (step " + std::to_string(status_.step) + ")");
  }
}

void PlanController::TouchDown(std::size_t sl, double t) {
  status_.stance[sl] = true;
  load_[sl] = 0.0;
  normal_W_[sl] = plan_.states[static_cast<std::size_t>(status_.step)].feet[sl].normal.normalized();
  Enter(ControllerPhase::kLoad, t);
  if (pattern_) touchdown_s_[sl] = t;  // it loads while the walk goes on (FinishStep follows at once)
}

void PlanController::AdvanceAwait(const Measured& m) {
  if (pending_) {
    TakePendingPlan(m);
    continue_requested_ = false;
    status_.step = 0;
    NextStepOrFinish(m);
  } else if (continue_requested_) {
    continue_requested_ = false;
    NextStepOrFinish(m);
  }
}

JointVector PlanController::Update(const RobotState& state) {
  Measured m;
  m.t = state.t;
  m.R = state.base_orientation_W.normalized().toRotationMatrix();
  m.p = state.base_position_W;
  m.v = state.base_linear_velocity_W;
  m.w_W = m.R * state.base_angular_velocity_B;
  m.q = state.q;
  m.qd = state.qd;
  m.contact = state.foot_contact;
  m.force_W = state.foot_force_W;
  for (Leg leg : kAllLegs) {
    m.feet_W[static_cast<std::size_t>(Index(leg))] = m.p + m.R * robot_.FootPosition(leg, LegJoints(m.q, leg));
  }
  m.com_W = m.p + m.R * robot_.CenterOfMass(m.q);

  if (!started_) {
    // Hold the pose the robot is found in until a plan arrives.
    started_ = true;
    reference_.position_W = m.p;
    reference_.orientation_W = Eigen::Quaterniond(m.R);
    MoveBaseTo(m.p, reference_.orientation_W, m.t, config_.base.min_shift_s);
    status_.phase_start_s = m.t;
    last_tick_s_ = m.t;
  }
  Advance(m);
  last_tick_s_ = m.t;
  EvaluateReference(m.t);
  if (pattern_) {
    // The pattern moves the CoM: the base is where the measured CoM offset puts it.
    const ComState com = pattern_->ComAt(pattern_time_s_);
    reference_.position_W.head<2>() = com.position - (m.com_W - m.p).head<2>();
    reference_.linear_velocity_W.head<2>() = clock_held_ ? Eigen::Vector2d::Zero() : com.velocity;
    reference_.linear_acceleration_W.head<2>() = clock_held_ ? Eigen::Vector2d::Zero() : com.acceleration;
  }
  status_.base_error_m = (reference_.position_W - m.p).norm();
  status_.step_max_base_error_m = std::max(status_.step_max_base_error_m, status_.base_error_m);
  return Torques(m);
}

Wrench PlanController::BaseWrench(const Measured& m) const {
  // Virtual model: the wrench on the trunk about the CoM that holds the base on its reference.
  const double mass = robot_.TotalMass();
  const Eigen::Matrix3d& R = m.R;
  const BaseReference& ref = reference_;
  const Eigen::Vector3d e_p = ref.position_W - m.p;
  const Eigen::Vector3d e_v = ref.linear_velocity_W - m.v;
  const Eigen::Vector3d e_R = RotationVector(ref.orientation_W * Eigen::Quaterniond(R).conjugate());
  const Eigen::Vector3d e_w = ref.angular_velocity_W - m.w_W;
  const BaseMotionConfig& b = config_.base;
  Wrench wrench;
  wrench.head<3>() = Eigen::Vector3d(0, 0, mass * kGravity) +
                     R * (b.kp_linear.cwiseProduct(R.transpose() * e_p) + b.kd_linear.cwiseProduct(R.transpose() * e_v)) +
                     mass * ref.linear_acceleration_W;
  wrench.tail<3>() =
      R * (b.kp_angular.cwiseProduct(R.transpose() * e_R) + b.kd_angular.cwiseProduct(R.transpose() * e_w));
  return wrench;
}

ForceDistribution PlanController::StanceForces(const Measured& m, const Wrench& wrench) {
  // The stance feet bear the wrench by their load; those at least half loaded make the support
  // polygon whose margin the status reports.
  std::vector<StanceFoot> feet;
  std::vector<Eigen::Vector3d> support;
  for (Leg leg : kAllLegs) {
    const std::size_t i = static_cast<std::size_t>(Index(leg));
    if (!status_.stance[i] || load_[i] <= 0.0) continue;
    StanceFoot f;
    f.leg = leg;
    f.position_W = m.feet_W[i];
    f.normal_W = normal_W_[i];
    f.load = load_[i];
    feet.push_back(f);
    if (load_[i] >= 0.5) support.push_back(m.feet_W[i]);
  }
  // A leg loading after touchdown pushes at least a little from the start.
  for (StanceFoot& f : feet) f.load = std::max(f.load, 0.05);
  status_.support_margin_m = support.empty() ? -1.0 : SupportPolygonMargin(support, m.com_W);

  ForceDistributionParams params;
  params.friction = stance_.Rules().friction;
  params.min_normal_force_N = stance_.Config().min_normal_force_N;
  return DistributeWrench(feet, m.com_W, wrench, params);
}

void PlanController::AddStanceTorques(const Measured& m, Leg leg, const Eigen::Matrix3d& J,
                                      const Eigen::Vector3d& force_W, Eigen::Vector3d& t) const {
  const std::size_t i = static_cast<std::size_t>(Index(leg));
  const Eigen::Vector3d q = LegJoints(m.q, leg);
  const Eigen::Vector3d qd = LegJoints(m.qd, leg);
  const Eigen::Matrix3d& R = m.R;
  const Eigen::Matrix3d Rd = reference_.orientation_W.toRotationMatrix();
  t -= J.transpose() * (R.transpose() * force_W);
  // Joint servo: the joints that keep the measured foot where it is with the base on its reference.
  // It fades on a foot the ground carries with less than half its share of the weight (measured),
  // which it would drag along the ground: an unloading leg, or one the trunk tips away from.
  const double half_share_N = 0.125 * robot_.TotalMass() * kGravity;
  const double grip = std::clamp(m.force_W[i].dot(normal_W_[i]) / half_share_N, 0.0, 1.0);
  const IkResult ik = robot_.SolveLegIk(leg, Rd.transpose() * (m.feet_W[i] - reference_.position_W));
  if (ik.status != IkResult::Status::kOutOfReach) {
    t += grip * config_.stance.kp.cwiseProduct(ik.q - q);
  }
  // Its damping acts on the joint rates the base's reference motion implies (a foot that stays
  // put under a moving base), not on every motion of the joints.
  const Eigen::Vector3d foot_rate_B = R.transpose() * (-reference_.linear_velocity_W -
                                                      reference_.angular_velocity_W.cross(m.feet_W[i] - reference_.position_W));
  Eigen::Vector3d qd_des = Eigen::Vector3d::Zero();
  if (std::abs(J.determinant()) > 1e-4) qd_des = J.partialPivLu().solve(foot_rate_B);
  t += config_.stance.kd.cwiseProduct(qd_des - qd);
}

void PlanController::AddSwingTorques(const Measured& m, Leg leg, const Eigen::Matrix3d& J, Eigen::Vector3d& t) {
  // Swing or search: follow the path under joint PD.
  const std::size_t i = static_cast<std::size_t>(Index(leg));
  const Eigen::Vector3d q = LegJoints(m.q, leg);
  const Eigen::Vector3d qd = LegJoints(m.qd, leg);
  const Eigen::Matrix3d& R = m.R;
  const double elapsed = m.t - status_.phase_start_s;
  Eigen::Vector3d acceleration_W = Eigen::Vector3d::Zero();
  if (status_.phase == ControllerPhase::kSwing) {
    const double along = SwingTime(m.t);
    const double rate = swing_hurried_at_ ? config_.swing.tip_speedup : 1.0;
    swing_target_W_ = swing_.Position(along);
    swing_velocity_W_ = rate * swing_.Velocity(along);
    acceleration_W = rate * rate * swing_.Acceleration(along);
  } else if (status_.phase == ControllerPhase::kSearch) {
    const Eigen::Vector3d n = plan_.states[static_cast<std::size_t>(status_.step)].feet[i].normal.normalized();
    const double depth = std::min(elapsed * config_.swing.search_speed_mps, config_.swing.search_depth_m);
    swing_target_W_ = search_start_W_ - depth * n;
    swing_velocity_W_ = -config_.swing.search_speed_mps * n;
  } else {
    swing_velocity_W_.setZero();
  }
  const IkResult ik = robot_.SolveLegIk(leg, R.transpose() * (swing_target_W_ - m.p));
  if (ik.status != IkResult::Status::kOutOfReach) swing_q_des_ = ik.q;
  const Eigen::Vector3d v_rel_B = R.transpose() * (swing_velocity_W_ - m.v - m.w_W.cross(swing_target_W_ - m.p));
  // The joint rates of the foot's velocity relative to the trunk, and the joint accelerations that
  // give the foot the path's acceleration beyond what those rates give it (the trunk taken as
  // still): the latter with the leg's inertia as a feed-forward.
  const bool regular = std::abs(J.determinant()) > 1e-4;
  Eigen::Vector3d qd_des = Eigen::Vector3d::Zero();
  Eigen::Vector3d qdd_des = Eigen::Vector3d::Zero();
  if (regular) {
    const Eigen::PartialPivLU<Eigen::Matrix3d> lu = J.partialPivLu();
    qd_des = lu.solve(v_rel_B);
    constexpr double kStep = 1e-4;  // [s] for the change of the Jacobian along the joint rates
    const Eigen::Vector3d jdot_qd = (robot_.FootJacobian(leg, q + kStep * qd) - J) * qd / kStep;
    qdd_des = lu.solve(R.transpose() * acceleration_W - jdot_qd);
  }
  t += config_.swing.kp.cwiseProduct(swing_q_des_ - q) + config_.swing.kd.cwiseProduct(qd_des - qd);
  if (regular) t += robot_.LegMassMatrix(leg, q) * qdd_des;
}

JointVector PlanController::Torques(const Measured& m) {
  const ForceDistribution forces = StanceForces(m, BaseWrench(m));
  const Eigen::Vector3d gravity_B = m.R.transpose() * Eigen::Vector3d(0, 0, -kGravity);
  JointVector tau = JointVector::Zero();
  for (Leg leg : kAllLegs) {
    // Gravity compensation of the leg, then its stance or swing servo.
    const std::size_t i = static_cast<std::size_t>(Index(leg));
    const Eigen::Vector3d q = LegJoints(m.q, leg);
    Eigen::Vector3d foot_B;
    Eigen::Matrix3d J;
    robot_.FootPositionAndJacobian(leg, q, &foot_B, &J);
    Eigen::Vector3d t = robot_.LegGravityTorques(leg, q, gravity_B);
    if (status_.stance[i]) {
      AddStanceTorques(m, leg, J, forces.forces_W[i], t);
    } else {
      AddSwingTorques(m, leg, J, t);
    }
    SetLegJoints(tau, leg, t);
  }
  const double limit = robot_.ContinuousTorqueLimit();
  return tau.cwiseMax(-limit).cwiseMin(limit);
}

}  // namespace rbcp
