#include "rbcp/stance/walking_pattern.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/support_polygon.h"

namespace rbcp {
namespace {

/// The feet of `state` on the ground, (x, y, z), without `swing_leg` (-1: all four).
std::vector<Eigen::Vector3d> FeetDown(const WholeBodyState& state, int swing_leg) {
  std::vector<Eigen::Vector3d> feet;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    if (leg != swing_leg) feet.push_back(state.feet[static_cast<std::size_t>(leg)].position);
  }
  return feet;
}

SupportPhase MakePhase(double start_s, double duration_s, int swing_leg, int state,
                       const std::vector<Eigen::Vector3d>& feet) {
  SupportPhase phase;
  phase.start_s = start_s;
  phase.end_s = start_s + duration_s;
  phase.swing_leg = swing_leg;
  phase.state = state;
  std::vector<Eigen::Vector2d> xy;
  for (const Eigen::Vector3d& f : feet) xy.push_back(f.head<2>());
  phase.polygon = ConvexHull2d(xy);
  return phase;
}

/// The time a min-jerk move (peak 1.875 times the mean rate) of the base from `from`'s height and
/// attitude to `to`'s takes at the timing's peak rates.
double BaseMoveS(const WholeBodyState& from, const WholeBodyState& to, const GaitTiming& timing) {
  const Eigen::Quaterniond q0(RotationFromRpy(from.base_rpy));
  const Eigen::Quaterniond q1(RotationFromRpy(to.base_rpy));
  return 1.875 * std::max(std::abs(to.base_position.z() - from.base_position.z()) / timing.base_rise_mps,
                          q0.angularDistance(q1) / timing.base_turn_radps);
}

Eigen::Vector2d Centre(const std::vector<Eigen::Vector3d>& feet) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& f : feet) sum += f.head<2>();
  return sum / static_cast<double>(feet.size());
}

}  // namespace

Eigen::Vector2d NearestWithMargin(const std::array<Eigen::Vector2d, 3>& tri, double margin, const Eigen::Vector2d& p) {
  const std::optional<std::array<Eigen::Vector2d, 3>> shrunk = ErodeTriangle(tri, margin);
  return shrunk ? ClosestPointInTriangle(*shrunk, p) : TriangleIncentre(tri);
}

namespace {

/// g / h of the pendulum of `model` [1/s^2].
double OmegaSquared(const ZmpPreviewModel& model) { return model.Params().gravity_mps2 / model.Params().com_height_m; }

/// The capture point of `com` on the pendulum of `model` (where a ZMP held still brings the CoM
/// to rest), or where the segment from it to the centre of the four feet of `state` first lies
/// `margin` inside them (the centre when none does).
Eigen::Vector2d CaptureWithin(const WholeBodyState& state, const ZmpPreviewModel& model, const ComState& com,
                              double margin) {
  const Eigen::Vector2d capture = com.position + com.velocity / std::sqrt(OmegaSquared(model));
  const std::vector<Eigen::Vector3d> four = FeetDown(state, -1);
  const auto margin_at = [&](const Eigen::Vector2d& p) { return SupportPolygonMargin(four, Eigen::Vector3d(p.x(), p.y(), 0.0)); };
  if (margin_at(capture) >= margin) return capture;
  const Eigen::Vector2d centre = Centre(four);
  if (margin_at(centre) < margin) return centre;
  // The margin rises along the segment towards the centre (the polygon is convex): bisect.
  double outside = 0.0, inside = 1.0;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (outside + inside);
    (margin_at(capture + mid * (centre - capture)) >= margin ? inside : outside) = mid;
  }
  return capture + inside * (centre - capture);
}

}  // namespace

const SupportPhase& WalkingPattern::PhaseAt(double t) const {
  RBCP_CHECK(!phases.empty(), "a walking pattern has phases");
  const auto it = std::upper_bound(phases.begin(), phases.end(), t,
                                   [](double time, const SupportPhase& p) { return time < p.end_s; });
  return it == phases.end() ? phases.back() : *it;
}

const SupportPhase& WalkingPattern::SwingOf(int state) const {
  // Each step is a four-foot phase and its swing, in the plan's order.
  const std::size_t index = 2 * static_cast<std::size_t>(state) - 1;
  RBCP_CHECK(state >= 1 && index < phases.size() && phases[index].state == state, "the pattern has this step");
  return phases[index];
}

namespace {

/// The samples k and k + 1 around time t and the weight of k + 1 (held beyond the end).
std::pair<std::size_t, double> Bracket(double t, double time_step_s, std::size_t samples) {
  RBCP_CHECK(samples > 0, "a walking pattern has samples");
  const double x = std::max(t, 0.0) / time_step_s;
  const std::size_t k = static_cast<std::size_t>(std::floor(x));
  if (k + 1 >= samples) return {samples - 1, 0.0};
  return {k, x - static_cast<double>(k)};
}

template <class T>
T Lerp(const std::vector<T>& v, const std::pair<std::size_t, double>& at) {
  const auto [k, w] = at;
  return w == 0.0 ? v[k] : T((1.0 - w) * v[k] + w * v[k + 1]);
}

}  // namespace

ComState WalkingPattern::ComAt(double t) const {
  const auto at = Bracket(t, time_step_s, com.position.size());
  ComState s;
  s.position = Lerp(com.position, at);
  s.velocity = Lerp(com.velocity, at);
  s.acceleration = Lerp(com.acceleration, at);
  s.zmp_error_sum = Lerp(com.zmp_error_sum, at);
  if (t >= Duration()) {
    s.velocity.setZero();
    s.acceleration.setZero();
  }
  return s;
}

Eigen::Vector2d WalkingPattern::ZmpReferenceAt(double t) const {
  return Lerp(zmp_reference, Bracket(t, time_step_s, zmp_reference.size()));
}

Eigen::Vector2d WalkingPattern::ZmpAt(double t) const { return Lerp(com.zmp, Bracket(t, time_step_s, com.zmp.size())); }

double WalkingPattern::MinZmpMargin() const {
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < com.zmp.size(); ++k) {
    const SupportPhase& phase = PhaseAt(static_cast<double>(k) * time_step_s);
    std::vector<Eigen::Vector3d> corners;
    for (const Eigen::Vector2d& v : phase.polygon) corners.emplace_back(v.x(), v.y(), 0.0);
    least = std::min(least, SupportPolygonMargin(corners, Eigen::Vector3d(com.zmp[k].x(), com.zmp[k].y(), 0.0)));
  }
  return least;
}

WalkingPattern PlanWalkingPattern(const ContactPlan& plan, const GaitTiming& timing, const ZmpPreviewModel& model,
                                  const Eigen::Vector2d& com_start_xy) {
  PatternStart start;
  start.com.position = com_start_xy;
  return PlanWalkingPattern(plan, timing, model, start);
}

WalkingPattern PlanWalkingPattern(const ContactPlan& plan, const GaitTiming& timing, const ZmpPreviewModel& model,
                                  const PatternStart& start) {
  if (plan.states.size() < 2) {
    throw InputError("walking pattern: expected a plan of at least two states, got " + std::to_string(plan.states.size()));
  }
  timing.Validate();
  if (!timing.step_swing_s.empty() && timing.step_swing_s.size() + 1 != plan.states.size()) {
    throw InputError("walking pattern: expected a swing duration per step (" + std::to_string(plan.states.size() - 1) +
                     "), got " + std::to_string(timing.step_swing_s.size()));
  }
  if (!timing.step_shift_s.empty() && timing.step_shift_s.size() + 1 != plan.states.size()) {
    throw InputError("walking pattern: expected a four-foot duration per step (" + std::to_string(plan.states.size() - 1) +
                     "), got " + std::to_string(timing.step_shift_s.size()));
  }
  if (!start.step_com.empty() && start.step_com.size() + 1 != plan.states.size()) {
    throw InputError("walking pattern: expected a CoM per step (" + std::to_string(plan.states.size() - 1) + "), got " +
                     std::to_string(start.step_com.size()));
  }
  ComState com = start.com;
  if (!com.position.allFinite() || !com.velocity.allFinite() || !com.acceleration.allFinite() ||
      !com.zmp_error_sum.allFinite() || (start.zmp && !start.zmp->allFinite())) {
    throw InputError("walking pattern: expected a finite CoM start");
  }
  WalkingPattern pattern;
  pattern.time_step_s = model.Params().time_step_s;

  // The phases, and the reference's corners: (time, point) where it stands still or starts to move.
  // From rest the ZMP stays under the CoM for half the start phase; a moving CoM's goes on from
  // the ZMP it follows.
  std::vector<std::pair<double, Eigen::Vector2d>> knots;
  if (start.zmp) {
    Eigen::Vector2d first = *start.zmp;
    if (start.come_to_rest) {
      // The ZMP steps to the capture point (the feet's forces change at once; the pendulum's
      // acceleration with it), so the CoM it follows slows to rest with no transient of the
      // preview's own: its state agrees with the reference from the start.
      first = CaptureWithin(plan.states.front(), model, com, timing.zmp_margin_m);
      com.acceleration = OmegaSquared(model) * (com.position - first);
    }
    knots = {{0.0, first}};
    if (start.hold_s > 0.0) knots.emplace_back(start.hold_s, first);
  } else {
    knots = {{0.0, com.position}, {timing.start_s / 2.0, com.position}};
  }
  double t = 0.0;
  for (std::size_t i = 1; i < plan.states.size(); ++i) {
    const WholeBodyState& before = plan.states[i - 1];
    const int swing = plan.states[i].moving_leg;
    if (swing < 0 || swing >= kNumLegs) {
      throw InputError("walking pattern: state " + std::to_string(i) + " has no moving leg (" + std::to_string(swing) + ")");
    }
    const int state = static_cast<int>(i);
    const std::vector<Eigen::Vector3d> four = FeetDown(before, -1);
    const std::vector<Eigen::Vector3d> stance = FeetDown(before, swing);
    const Eigen::Vector2d preferred = start.step_com.empty() ? Centre(four) : start.step_com[i - 1];
    const Eigen::Vector2d target =
        NearestWithMargin({stance[0].head<2>(), stance[1].head<2>(), stance[2].head<2>()}, timing.zmp_margin_m, preferred);
    // Four feet down as long as the ZMP needs to reach the next triangle (across the diagonal
    // between two swings on opposite sides, a few centimetres along one side).
    const double move_s = (target - knots.back().second).norm() / timing.zmp_speed_mps;
    const double given_shift = timing.step_shift_s.empty() ? std::numeric_limits<double>::quiet_NaN() : timing.step_shift_s[i - 1];
    // The ZMP stays in the last triangle while the leg that touched down loads, and is in the
    // next one when the leg that lifts next begins to unload. A point the margin inside a
    // triangle is within it for margin / speed before and after it: the holds are that much
    // shorter than the ramps (and in a phase too short for them, shrink to leave it a fifth).
    const double lead_s = timing.zmp_margin_m / timing.zmp_speed_mps;
    const double load_hold_s = std::max(0.0, timing.load_s - lead_s);
    const double unload_hold_s = std::max(0.0, timing.unload_s - lead_s);
    const double shift_s =
        i > 1 && !std::isnan(given_shift)
            ? given_shift
            : std::max({timing.four_foot_s, load_hold_s + move_s + unload_hold_s, BaseMoveS(before, plan.states[i], timing)});
    const double four_foot_s = i > 1 ? shift_s : start.zmp ? start.hold_s + shift_s : timing.start_s;
    pattern.phases.push_back(MakePhase(t, four_foot_s, -1, state, four));
    const double moving_from = i > 1 ? t : start.zmp ? start.hold_s : knots.back().first;
    const double holds_s = load_hold_s + unload_hold_s;
    const double scale = holds_s > 0.0 ? std::min(1.0, 0.8 * (t + four_foot_s - moving_from) / holds_s) : 0.0;
    if ((i > 1 || start.zmp) && scale * load_hold_s > 0.0) {
      knots.emplace_back(moving_from + scale * load_hold_s, knots.back().second);
    }
    if (scale * unload_hold_s > 0.0) knots.emplace_back(t + four_foot_s - scale * unload_hold_s, target);
    t += four_foot_s;
    knots.emplace_back(t, target);
    const double given = timing.step_swing_s.empty() ? std::numeric_limits<double>::quiet_NaN() : timing.step_swing_s[i - 1];
    const double swing_s = std::isnan(given) ? timing.swing_s : given;
    pattern.phases.push_back(MakePhase(t, swing_s, swing, state, stance));
    t += swing_s;
    knots.emplace_back(t, target);
  }
  const std::vector<Eigen::Vector3d> last = FeetDown(plan.states.back(), -1);
  pattern.phases.push_back(
      MakePhase(t, timing.four_foot_s + timing.final_s, -1, static_cast<int>(plan.states.size()) - 1, last));
  const Eigen::Vector2d rest = start.step_com.empty() ? Centre(last) : start.step_com.back();
  knots.emplace_back(t + timing.four_foot_s, rest);
  t += timing.four_foot_s + timing.final_s;
  knots.emplace_back(t, rest);

  // The reference, piecewise linear through the knots, one sample per time step.
  const std::size_t samples = static_cast<std::size_t>(std::ceil(t / pattern.time_step_s)) + 1;
  pattern.zmp_reference.reserve(samples);
  std::size_t knot = 0;
  for (std::size_t k = 0; k < samples; ++k) {
    const double time = std::min(static_cast<double>(k) * pattern.time_step_s, t);
    while (knot + 2 < knots.size() && time > knots[knot + 1].first) ++knot;
    const auto& [t0, p0] = knots[knot];
    const auto& [t1, p1] = knots[knot + 1];
    const double s = t1 > t0 ? std::clamp((time - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
    pattern.zmp_reference.push_back(p0 + s * (p1 - p0));
  }
  if (start.zmp && start.come_to_rest) {
    // The ZMP held still: the pendulum's own jerk, omega^2 times the velocity.
    com.zmp_error_sum = ZmpErrorSumForJerk(model, com, pattern.zmp_reference, OmegaSquared(model) * com.velocity);
  }
  pattern.com = PreviewCom(model, com, pattern.zmp_reference);
  return pattern;
}

}  // namespace rbcp
