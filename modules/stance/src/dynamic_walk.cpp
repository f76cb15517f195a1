#include "rbcp/stance/dynamic_walk.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/support_polygon.h"

namespace rbcp {
namespace {

constexpr double kCheckIntervalS = 0.04;  // [s] between two poses CheckDynamicStep checks
constexpr double kSlowdown = 1.5;         // a failing step's phases last this much longer ...
constexpr int kMaxSlowdowns = 3;          // ... at most this many times

/// The swing path config of the dynamic walk: the stance rules' path at its own swing speed.
SwingPathConfig DynamicSwingPath(const StanceConfig& config) {
  SwingPathConfig path = config.swing;
  path.speed_mps = config.dynamic_walk.swing_speed_mps;
  path.min_duration_s = config.dynamic_walk.min_swing_s;
  return path;
}

/// The CoM of `state` in the world frame.
Eigen::Vector3d StateCom(const RobotModel& robot, const WholeBodyState& state) {
  return BasePose(state) * robot.CenterOfMass(state.joints);
}

StanceVerdict Failure(StanceCheck check, StepPhase phase, std::string detail) {
  StanceVerdict v;
  v.check = check;
  v.phase = phase;
  v.detail = std::move(detail);
  return v;
}

/// Pattern times at which CheckDynamicStep looks at step `index`: every kCheckIntervalS from the
/// previous touch-down to its own, both ends included.
std::vector<double> CheckTimes(const WalkingPattern& pattern, int index) {
  const SupportPhase& swing = pattern.SwingOf(index);
  const double begin = index == 1 ? 0.0 : pattern.SwingOf(index - 1).end_s;
  std::vector<double> times;
  const int n = std::max(1, static_cast<int>(std::ceil((swing.end_s - begin) / kCheckIntervalS)));
  for (int k = 0; k <= n; ++k) times.push_back(begin + (swing.end_s - begin) * k / n);
  return times;
}

/// The joints that put every foot of `feet` but `skip` where it is with the base at base_W,
/// into *q (the skip leg's joints are left as they are): within the joint bounds, each knee bent
/// at least the robot's margin (away from the stretched leg's singularity). The planner's
/// hip-distance margins, which allow for a base tracked a centimetre off its plan pose, are not
/// asked for: these poses are the walk itself. Empty when solved, else what is out of reach (and
/// that leg in *failed).
std::string SolveWalkStance(const RobotModel& robot, const Eigen::Isometry3d& base_W, const FootContacts& feet,
                            int skip, JointVector* q, std::optional<Leg>* failed) {
  const Eigen::Isometry3d T_BW = base_W.inverse();
  for (Leg leg : kAllLegs) {
    if (Index(leg) == skip) continue;
    const Eigen::Vector3d p_B = T_BW * feet[static_cast<std::size_t>(Index(leg))].position;
    const std::string distance = FixedNumber((p_B - robot.HipPosition(leg)).norm(), 3) + " m from its hip";
    const IkResult ik = robot.SolveLegIk(leg, p_B);
    if (!ik.ok() || !robot.KneeBent(ik.q)) {
      *failed = leg;
      return std::string(LegName(leg)) + (ik.ok() ? " knee straighter than the margin, " : " foot beyond the leg's reach, ") +
             distance;
    }
    SetLegJoints(*q, leg, ik.q);
  }
  return {};
}

}  // namespace

SwingTrajectory DynamicSwing(const StanceChecker& checker, const ContactPlan& plan, int index,
                             const std::optional<Eigen::Vector3d>& start_W) {
  RBCP_CHECK(index >= 1 && static_cast<std::size_t>(index) < plan.states.size(), "a step of the plan");
  const WholeBodyState& to = plan.states[static_cast<std::size_t>(index)];
  const WholeBodyState& from = plan.states[static_cast<std::size_t>(index - 1)];
  RBCP_CHECK(to.moving_leg >= 0 && to.moving_leg < kNumLegs, "a step has a moving leg");
  const std::size_t leg = static_cast<std::size_t>(to.moving_leg);
  const SwingPathConfig path = DynamicSwingPath(checker.Config());
  const Eigen::Vector3d start = start_W.value_or(from.feet[leg].position);
  const SwingTrajectory swing =
      to.HasSwing()
          ? SwingTrajectory::Given(start, to.feet[leg].position, to.swing_apex_z, to.swing_bow, path)
          : checker.PlanSwing(static_cast<Leg>(to.moving_leg), from.feet[leg].position, to.feet[leg].position,
                              BasePose(to), to.joints)
                .StartingAt(start)
                .Retimed(path);
  // The plan's time, or longer where the path from where the foot really is needs more at the
  // clock's peak foot speed (a foot that starts off its foothold: the walk then lags).
  return to.HasTiming() ? swing.Lasting(std::max(swing.Duration(), to.touch_down_s - to.lift_off_s)) : swing;
}

PatternStart DynamicWalkAtRest(const StanceChecker& checker, const ContactPlan& plan) {
  RBCP_CHECK(!plan.states.empty(), "a plan with a first state");
  PatternStart rest;
  rest.com.position = StateCom(checker.Robot(), plan.states.front()).head<2>();
  return rest;
}

WalkingPattern DynamicWalkPattern(const StanceChecker& checker, const ContactPlan& plan, PatternStart start) {
  if (plan.states.size() < 2) {
    throw InputError("dynamic walk: expected a plan of at least two states, got " + std::to_string(plan.states.size()));
  }
  const RobotModel& robot = checker.Robot();
  const DynamicWalkConfig& walk = checker.Config().dynamic_walk;
  // The pendulum's height: the CoM above the mean height of the first stance's feet.
  const WholeBodyState& first = plan.states.front();
  double feet_z = 0.0;
  for (const FootContact& f : first.feet) feet_z += f.position.z() / kNumLegs;
  ZmpPreviewParams params;
  static_cast<ZmpPreviewSettings&>(params) = walk.preview;
  params.com_height_m = std::max(StateCom(robot, first).z() - feet_z, 0.1);
  const ZmpPreviewModel model(params);

  GaitTiming timing;
  static_cast<GaitPhases&>(timing) = walk.gait;
  timing.swing_s = walk.min_swing_s;  // every step has its own below
  const bool timed = plan.Timed();
  start.step_com.clear();
  for (std::size_t i = 1; i < plan.states.size(); ++i) {
    const WholeBodyState& s = plan.states[i];
    if (s.moving_leg < 0 || s.moving_leg >= kNumLegs) {
      throw InputError("dynamic walk: state " + std::to_string(i) + " has no moving leg (" +
                       std::to_string(s.moving_leg) + ")");
    }
    timing.step_swing_s.push_back(DynamicSwing(checker, plan, static_cast<int>(i)).Duration());
    timing.step_shift_s.push_back(timed && i > 1 ? s.lift_off_s - plan.states[i - 1].touch_down_s
                                                 : std::numeric_limits<double>::quiet_NaN());
    start.step_com.push_back(StateCom(robot, s).head<2>());
  }
  return PlanWalkingPattern(plan, timing, model, start);
}

DynamicStepCheck CheckDynamicStep(const StanceChecker& checker, const ContactPlan& plan, const WalkingPattern& pattern,
                                  int index) {
  RBCP_CHECK(index >= 1 && static_cast<std::size_t>(index) < plan.states.size(), "a step of the plan");
  const RobotModel& robot = checker.Robot();
  const WholeBodyState& from = plan.states[static_cast<std::size_t>(index - 1)];
  const WholeBodyState& to = plan.states[static_cast<std::size_t>(index)];
  const int lifting = to.moving_leg;
  const SupportPhase& swing = pattern.SwingOf(index);
  const double shift_begin = index == 1 ? 0.0 : pattern.SwingOf(index - 1).end_s;
  const Eigen::Quaterniond q_from(RotationFromRpy(from.base_rpy));
  const Eigen::Quaterniond q_to(RotationFromRpy(to.base_rpy));
  const SwingTrajectory path = DynamicSwing(checker, plan, index);
  const double start_z = path.Position(0.0).z();
  const double end_z = to.feet[static_cast<std::size_t>(lifting)].position.z();

  DynamicStepCheck out;
  for (double t : CheckTimes(pattern, index)) {
    const bool swinging = t > swing.start_s && t < swing.end_s;
    const StepPhase phase = swinging ? StepPhase::kSwing : StepPhase::kShift;
    const int skip = swinging ? lifting : -1;
    // The feet down: the step's own once its foot has touched down (the last sample).
    const FootContacts& feet = t >= swing.end_s ? to.feet : from.feet;
    const auto fail = [&](StanceCheck check, const std::string& detail, std::optional<Leg> leg = std::nullopt) {
      if (out.verdict.ok()) {
        out.verdict = Failure(check, phase, "at " + FixedNumber(t, 2) + " s of the walk: " + detail);
        out.verdict.leg = leg;
        out.time_s = t;
      }
    };
    // Where the pattern has the ZMP, against the feet down.
    const ComState com = pattern.ComAt(t);
    std::vector<Eigen::Vector3d> support;
    for (const Eigen::Vector2d& v : pattern.PhaseAt(t).polygon) support.emplace_back(v.x(), v.y(), 0.0);
    const Eigen::Vector2d zmp = pattern.ZmpAt(t);
    const double zmp_margin = SupportPolygonMargin(support, Eigen::Vector3d(zmp.x(), zmp.y(), 0.0));
    out.min_zmp_margin_m = std::min(out.min_zmp_margin_m, zmp_margin);
    if (zmp_margin < 0.0) fail(StanceCheck::kSupport, "the ZMP " + FixedNumber(-zmp_margin, 3) + " m outside the feet");

    // The base: height and attitude blend to the step's over the four-foot phase, x and y carry
    // the CoM where the pattern has it.
    const double u =
        swing.start_s > shift_begin ? std::clamp((t - shift_begin) / (swing.start_s - shift_begin), 0.0, 1.0) : 1.0;
    const double w = MinJerk(u);
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.linear() = q_from.slerp(w, q_to).toRotationMatrix();
    base.translation() = from.base_position + w * (to.base_position - from.base_position);
    JointVector q = to.joints;  // the swinging leg's for its share of the CoM
    std::string unreachable;
    std::optional<Leg> unreachable_leg;
    for (int pass = 0; pass < 2 && unreachable.empty(); ++pass) {  // the CoM's offset depends on the joints
      const Eigen::Vector3d offset = base.linear() * robot.CenterOfMass(q);
      base.translation().head<2>() = com.position - offset.head<2>();
      unreachable = SolveWalkStance(robot, base, feet, skip, &q, &unreachable_leg);
    }
    if (!unreachable.empty()) {
      fail(StanceCheck::kReach, unreachable, unreachable_leg);
      continue;
    }
    // The swinging foot on its path, once it is 2 cm above the foothold it rises from, or then
    // descends to (as the planner checks the leg along the path: SwingTrajectory::LegCheckPoints).
    std::optional<Eigen::Vector3d> swing_q;
    if (swinging) {
      const double along = (t - swing.start_s) * path.Duration() / (swing.end_s - swing.start_s);
      const Eigen::Vector3d foot_W = path.Position(along);
      if (foot_W.z() > (path.Phase(along) <= 0.5 ? start_z : end_z) + 0.02) {
        const IkResult ik = robot.SolveLegIk(static_cast<Leg>(lifting), base.inverse() * foot_W);
        if (!ik.ok()) fail(StanceCheck::kReach, "the swinging foot beyond its leg's reach", static_cast<Leg>(lifting));
        else swing_q = ik.q;
      }
    }
    if (checker.HasTerrain()) {
      CollisionReport hit = checker.TerrainCollision().CheckTrunk(base);
      std::optional<Leg> hit_leg;
      for (Leg leg : kAllLegs) {
        if (hit.collision) break;
        if (Index(leg) != skip) hit = checker.TerrainCollision().CheckLeg(leg, base, LegJoints(q, leg), true);
        if (hit.collision) hit_leg = leg;
      }
      if (hit.collision) fail(StanceCheck::kCollision, hit.first_shape + " on the terrain", hit_leg);
      if (swing_q) {
        const CollisionReport leg_hit = checker.TerrainCollision().CheckLeg(static_cast<Leg>(lifting), base, *swing_q, true);
        if (leg_hit.collision) fail(StanceCheck::kSwingTerrain, leg_hit.first_shape + " on the terrain as it swings");
      }
    }
    const Eigen::Vector3d com_W = base * robot.CenterOfMass(q);
    double torque = 0.0;
    const StanceVerdict v = checker.Torques(base, q, feet, skip, com_W,
                                            Eigen::Vector3d(com.acceleration.x(), com.acceleration.y(), 0.0), &torque);
    out.max_torque_Nm = std::max(out.max_torque_Nm, torque);
    if (!v.ok()) fail(v.check, v.detail);
  }
  return out;
}

std::vector<DynamicStepCheck> TimeDynamicWalk(const StanceChecker& checker, ContactPlan* plan, int keep_steps) {
  RBCP_CHECK(plan != nullptr, "a plan to time");
  const std::size_t steps = plan->states.size() - 1;
  const std::size_t kept = static_cast<std::size_t>(std::clamp(keep_steps, 0, static_cast<int>(steps)));
  // The kept steps' durations: each one's four-foot phase and swing.
  std::vector<std::pair<double, double>> given;
  for (std::size_t i = 1; i <= kept; ++i) {
    const WholeBodyState& s = plan->states[i];
    if (!s.HasTiming() || (i > 1 && !plan->states[i - 1].HasTiming())) {
      throw InputError("dynamic walk: step " + std::to_string(i) + " is to keep its timing but has none");
    }
    given.emplace_back(i > 1 ? s.lift_off_s - plan->states[i - 1].touch_down_s : 0.0, s.touch_down_s - s.lift_off_s);
  }
  plan->ClearTiming();
  // The other steps' phases at the dynamic walk's own pace, then slowed.
  const PatternStart rest = DynamicWalkAtRest(checker, *plan);
  const WalkingPattern nominal = DynamicWalkPattern(checker, *plan, rest);
  std::vector<int> slowdowns(steps, 0);
  std::vector<DynamicStepCheck> checks(steps);
  const auto time_and_check = [&] {
    double t = 0.0;
    for (std::size_t i = 1; i <= steps; ++i) {
      const SupportPhase& swing = nominal.SwingOf(static_cast<int>(i));
      double shift_s = swing.start_s - (i == 1 ? 0.0 : nominal.SwingOf(static_cast<int>(i) - 1).end_s);
      double swing_s = swing.end_s - swing.start_s;
      if (i <= kept) {
        if (i > 1) shift_s = given[i - 1].first;  // the first step's four-foot phase is the walk's start
        swing_s = given[i - 1].second;
      } else {
        const double k = std::pow(kSlowdown, slowdowns[i - 1]);
        if (i > 1) shift_s *= k;
        swing_s *= k;
      }
      WholeBodyState& s = plan->states[i];
      s.lift_off_s = t + shift_s;
      s.touch_down_s = s.lift_off_s + swing_s;
      t = s.touch_down_s;
    }
    const WalkingPattern pattern = DynamicWalkPattern(checker, *plan, rest);
    for (std::size_t i = 1; i <= steps; ++i) checks[i - 1] = CheckDynamicStep(checker, *plan, pattern, static_cast<int>(i));
  };
  const auto pace_fails = [&](std::size_t i) {
    const StanceCheck c = checks[i].verdict.check;
    return c == StanceCheck::kTorque || c == StanceCheck::kBalance || c == StanceCheck::kSupport;
  };
  for (int round = 0;; ++round) {
    time_and_check();
    if (round == kMaxSlowdowns) break;
    bool slowed = false;
    for (std::size_t i = kept; i < steps; ++i) {
      if (pace_fails(i) && slowdowns[i] < kMaxSlowdowns) {
        ++slowdowns[i];
        slowed = true;
      }
    }
    if (!slowed) break;
  }
  // A step no slower pace cured keeps its own: a slow step is not free (its leg hangs in the
  // air, its CoM waits on three feet).
  bool reverted = false;
  for (std::size_t i = kept; i < steps; ++i) {
    if (pace_fails(i) && slowdowns[i] > 0) {
      slowdowns[i] = 0;
      reverted = true;
    }
  }
  if (reverted) time_and_check();
  for (std::size_t i = 0; i < steps; ++i) checks[i].slowdowns = slowdowns[i];
  return checks;
}

}  // namespace rbcp
