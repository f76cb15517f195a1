#pragma once
/// The walking pattern of a contact plan: its support phases on a clock, the ZMP reference they
/// imply and, by ZMP preview control, the CoM trajectory whose ZMP follows it. The base moves
/// while a leg swings; the four-foot phase between two swings is only the time the ZMP takes to
/// move from one support triangle to the next.
///
/// During the swing of a plan state's moving leg the support is the other three feet; the ZMP
/// reference stands at the point of that triangle, shrunk inward by the ZMP margin, nearest the
/// CoM the plan holds during that swing (PatternStart::step_com; without it, the centre of the four
/// feet before the step: the least sway that keeps the margin). It is the triangle's incentre when
/// the triangle is too small for the margin. Between two swings all four feet are down and the
/// reference stays where it was while the leg that touched down loads (load_s), moves in a straight
/// line to the next point at most at zmp_speed_mps, and is there before the next leg unloads
/// (unload_s): a leg gives up its load only with the ZMP over the feet that stay down;
/// the base also takes that time to reach the height and attitude of the step's plan state, which
/// a swing keeps (the planner checked it there). A pattern starts from the CoM at rest, held there
/// for the first half of the start phase (the preview needs to see a change coming to prepare for
/// it), and ends at rest at the plan's last CoM (or the centre of the last four feet). A pattern
/// that continues a walk (the next piece of a plan, the CoM moving) starts from the CoM's state
/// and the ZMP it follows, with a four-foot phase like any other.

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "rbcp/stance/gait_config.h"
#include "rbcp/stance/zmp_preview.h"
#include "rbcp/core/contact_plan.h"

namespace rbcp {

/// How long each phase of a step lasts: the gait's phases and each swing's duration.
struct GaitTiming : GaitPhases {
  double swing_s = 0.0;
  /// Per step (plan states 1..n, in order): the swing's own duration [s], e.g. the time the foot
  /// takes along the swing path the plan carries (DynamicSwing); empty, or NaN for a step:
  /// swing_s.
  std::vector<double> step_swing_s;
  /// Per step likewise: the four-foot phase before its swing [s], e.g. a timed plan's (from its
  /// previous touch-down to its lift-off). Empty, or NaN for a step, and always for the first
  /// step (its four-foot phase is start_s from rest, the hold and the shift of a walk going on):
  /// as long as the ZMP and the base need, at least four_foot_s.
  std::vector<double> step_shift_s;

  template <class Visitor>
  void Serialize(Visitor* v) {
    GaitPhases::Serialize(v);
    const Bounds duration = bounds::Positive().AtMost(60.0);
    v->Visit("swing_s", &swing_s, "s", duration, "one leg in the air, where step_swing_s gives none");
    for (double s : step_swing_s) {
      v->Rule("step_swing_s", std::isnan(s) || duration.Holds(s), "NaN or a duration in (0, 60] s", ConfigNumber(s));
    }
    for (double s : step_shift_s) {
      v->Rule("step_shift_s", std::isnan(s) || duration.Holds(s), "NaN or a duration in (0, 60] s", ConfigNumber(s));
    }
  }
  /// Throws InputError for a field outside its bounds.
  void Validate(const std::string& where = "gait timing") const { ValidateConfig(*this, where); }
};

/// A stretch of time with one set of feet down.
struct SupportPhase {
  double start_s = 0.0;
  double end_s = 0.0;
  int swing_leg = -1;  ///< Index(Leg) of the leg in the air; -1: all four feet down
  int state = 0;       ///< the plan state whose step this phase belongs to (its moving leg swings)
  std::vector<Eigen::Vector2d> polygon;  ///< the feet down, (x, y), counter-clockwise convex hull
};

/// A contact plan's support phases, ZMP reference and CoM trajectory, sampled every time step of
/// the preview model from t = 0.
struct WalkingPattern {
  double time_step_s = 0.0;
  std::vector<SupportPhase> phases;           ///< in time order, back to back
  std::vector<Eigen::Vector2d> zmp_reference; ///< per sample
  ComTrajectory com;                          ///< per sample; com.zmp is the ZMP it implies

  double Duration() const { return phases.empty() ? 0.0 : phases.back().end_s; }
  /// The plan's steps the pattern walks (a four-foot phase and a swing each, then the last phase).
  int Steps() const { return static_cast<int>(phases.size() / 2); }
  /// The phase at time t (the last one beyond the end).
  const SupportPhase& PhaseAt(double t) const;
  /// The swing of plan state `state`'s moving leg (states 1..n).
  const SupportPhase& SwingOf(int state) const;
  /// The CoM at time t, between samples by linear interpolation (held beyond the end).
  ComState ComAt(double t) const;
  /// The ZMP reference at time t, likewise.
  Eigen::Vector2d ZmpReferenceAt(double t) const;
  /// The ZMP of the CoM trajectory at time t, likewise.
  Eigen::Vector2d ZmpAt(double t) const;
  /// The least signed distance of the CoM trajectory's ZMP to its support polygon over every
  /// sample [m]: positive when the ZMP never leaves the support.
  double MinZmpMargin() const;
};

/// Where a walking pattern begins.
struct PatternStart {
  ComState com;
  /// The ZMP a moving CoM follows now; none: the CoM is at rest (start_s applies).
  std::optional<Eigen::Vector2d> zmp;
  /// With `zmp`: how long the reference stays there before the first four-foot phase begins
  /// [s]. A piece of plan taken when a foot touched down before its swing's end goes on with the
  /// rest of that swing's time, as the pattern walked before did: the CoM's motion was timed for
  /// it, and dropping it asks for the next shift at once (tens of m/s^2 from the preview).
  double hold_s = 0.0;
  /// With `zmp`: the CoM moves for a walk this plan does not go on with (its first step is not
  /// the one the CoM was headed for). The reference starts at the CoM's capture point instead,
  /// where a ZMP held still brings it to rest (moved towards the centre of the first state's four
  /// feet until it lies the ZMP margin inside them), and stays there hold_s; the CoM starts with
  /// the acceleration and the preview's integral of a ZMP already there. The plan is then walked
  /// from rest, as the planner checked it.
  bool come_to_rest = false;
  /// Per step (plan states 1..n): the CoM (x, y) the plan holds during the step's swing (its
  /// base pose's, where the planner checked the swing). The ZMP reference of a swing stands at
  /// the point of the shrunk support triangle nearest it, and the CoM stays near the plan's; the
  /// last one is where the CoM comes to rest. Empty: nearest the centre of the four feet before
  /// the step, and at rest over the centre of the last four.
  std::vector<Eigen::Vector2d> step_com;
};

/// The walking pattern of `plan` (at least two states) from `start`. Throws InputError for a plan
/// of fewer than two states, a state whose moving leg is not 0..3, a non-finite start, or a
/// timing out of bounds.
WalkingPattern PlanWalkingPattern(const ContactPlan& plan, const GaitTiming& timing, const ZmpPreviewModel& model,
                                  const PatternStart& start);
/// The same with the CoM at rest at `com_start_xy`.
WalkingPattern PlanWalkingPattern(const ContactPlan& plan, const GaitTiming& timing, const ZmpPreviewModel& model,
                                  const Eigen::Vector2d& com_start_xy);

/// The point nearest `p` of the triangle shrunk inward by `margin` (ErodeTriangle); the incentre
/// when the triangle's inscribed circle is not larger than `margin`.
Eigen::Vector2d NearestWithMargin(const std::array<Eigen::Vector2d, 3>& tri, double margin, const Eigen::Vector2d& p);

}  // namespace rbcp
