#include "rbcp/root_planner/root_planner.h"

#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/goals/GoalState.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <tuple>
#include <optional>
#include <random>
#include <sstream>

#include "kinodynamic_birrt.h"
#include "rbcp/affordance/surface_graph.h"
#include "rbcp/core/angle.h"
#include "rbcp/core/config_checks.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/rom.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

// The rest yaw that gives the yaw `yaw` at velocity v (the yaw model inverted): the direction r
// with w v/|v| + (1 - w) e(r) parallel to e(yaw). When the speed is at or above the blend speed,
// or no such r exists, the yaw itself.
double RestYawFor(const YawModel& model, const Eigen::Vector3d& v, double yaw) {
  const Eigen::Vector2d vxy = v.head<2>();
  const double speed = vxy.norm();
  const double x = std::min(1.0, speed / model.blend_speed);
  const double w = x * x * (3.0 - 2.0 * x);
  if (speed <= 0.0 || w >= 1.0) return WrapAngle(yaw);
  const Eigen::Vector2d e(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d d = vxy / speed;
  // |lambda e - w d| = 1 - w with lambda > 0.
  const double c = e.dot(d);
  const double disc = w * w * c * c - w * w + (1.0 - w) * (1.0 - w);
  if (disc < 0.0) return WrapAngle(yaw);
  const double lambda = w * c + std::sqrt(disc);
  if (lambda <= 0.0) return WrapAngle(yaw);
  const Eigen::Vector2d r = (lambda * e - w * d) / (1.0 - w);
  return std::atan2(r.y(), r.x());
}

// Random shortcut: replaces the part between two grid times by one steered piece when that is
// valid and shorter. The first attempt spans the whole path.
RootPath Shortcut(RootPath path, const detail::KinodynamicMotionValidator& validator, int iterations,
                  std::uint64_t seed, const ompl::base::PlannerTerminationCondition& ptc) {
  std::mt19937_64 rng(seed);
  const double h = validator.Settings().time_step;
  for (int it = 0; it < iterations && !ptc(); ++it) {
    const double T = path.Duration();
    const long n = std::lround(T / h);
    if (n < 2) break;
    long a = 0;
    long b = n;
    if (it > 0) {
      a = std::uniform_int_distribution<long>(0, n - 2)(rng);
      b = std::uniform_int_distribution<long>(a + 2, n)(rng);
    }
    const double t1 = static_cast<double>(a) * h;
    const double t2 = b == n ? T : static_cast<double>(b) * h;
    const RootPathSample s1 = path.Sample(t1);
    const RootPathSample s2 = path.Sample(t2);
    auto piece = validator.Steer(PointState{s1.p, s1.v}, s1.rest_yaw, PointState{s2.p, s2.v}, s2.rest_yaw);
    if (!piece || piece->Duration() >= (t2 - t1) - 0.5 * h) continue;
    if (!validator.IsValid(*piece)) continue;
    RootPath shorter(path.Yaw());
    const RootPath before = path.Part(0.0, t1);
    const RootPath after = path.Part(t2, T);
    for (const auto& s : before.Segments()) shorter.Append(s);
    if (piece->Duration() > 0.0) shorter.Append(*piece);
    for (const auto& s : after.Segments()) shorter.Append(s);
    path = std::move(shorter);
  }
  return path;
}

// Horizontal straightening: the path is cut into pieces of about knot_spacing [s] (on the
// steering grid). Each iteration takes a run of knots (the whole path first, then random runs) and
// moves the inner ones horizontally onto the straight line between the run's ends, or halfway
// there, at the same fraction of the run's horizontal length, keeping their times and heights;
// their horizontal velocities turn along the line with their speed kept. The pieces of the run are
// re-steered and the move kept when every piece is valid and the run takes at most one time step
// per piece longer (the steering grid), the whole path at most max_duration long. Random
// shortcuts are straight in 3D, so across a plinth or a stair flight they cannot skip the tree
// states the path climbs through, often far to one side; straightening in the horizontal plane
// only keeps the height profile and draws such detours (and the heading) toward the straight line.
constexpr double kStraightTolerance = 0.005;  // [m] knots this close to the line are not moved
constexpr double kMaxStraightenGrowth = 1.1;  // straightening makes a path at most 10 % longer
constexpr double kTurnOnTheSpotRate = 0.25;   // [rad/s] heading rate of a path that only turns

// The knots of straightening: the path's samples every `spacing` [s] from its start, and its end.
std::vector<RootPathSample> Knots(const RootPath& path, double spacing) {
  const double T = path.Duration();
  std::vector<RootPathSample> knots;
  for (double t = 0.0; t < T - 0.5 * spacing; t += spacing) knots.push_back(path.Sample(t));
  knots.push_back(path.Sample(T));
  return knots;
}

// The parts of the path between consecutive knots: pieces[k] runs from knots[k] to knots[k + 1].
std::vector<RootPath> PiecesBetween(const RootPath& path, const std::vector<RootPathSample>& knots) {
  std::vector<RootPath> pieces;
  for (std::size_t k = 0; k + 1 < knots.size(); ++k) pieces.push_back(path.Part(knots[k].t, knots[k + 1].t));
  return pieces;
}

// Where the knots i..j of a run go on the straight line between its ends.
struct RunLine {
  Eigen::Vector2d dir;                   // unit horizontal direction from knot i to knot j
  std::vector<Eigen::Vector2d> on_line;  // each knot's point on the line, i..j
  double deviation = 0.0;                // [m] the largest horizontal distance of a knot from its point
};

// The line of the run of knots i..j, each knot's point on it at the knot's fraction of the run's
// horizontal length; nullopt when the run's ends lie (horizontally) at the same place.
std::optional<RunLine> LineOfRun(const std::vector<RootPathSample>& knots, long i, long j) {
  const Eigen::Vector2d A = knots[static_cast<std::size_t>(i)].p.head<2>();
  const Eigen::Vector2d B = knots[static_cast<std::size_t>(j)].p.head<2>();
  if ((B - A).norm() < 1e-6) return std::nullopt;
  RunLine line;
  line.dir = (B - A).normalized();
  std::vector<double> arc{0.0};
  for (long k = i + 1; k <= j; ++k) {
    arc.push_back(arc.back() + (knots[static_cast<std::size_t>(k)].p - knots[static_cast<std::size_t>(k - 1)].p).head<2>().norm());
  }
  for (long k = i; k <= j; ++k) {
    const std::size_t m = static_cast<std::size_t>(k - i);
    line.on_line.push_back(A + (arc[m] / arc.back()) * (B - A));
    line.deviation = std::max(line.deviation, (knots[static_cast<std::size_t>(k)].p.head<2>() - line.on_line.back()).norm());
  }
  return line;
}

// The knots i..j with the inner ones moved horizontally the fraction `blend` of the way to their
// points on the line; their horizontal velocities turn as far towards the line's direction, their
// speed kept (within the per-axis bound v_max).
std::vector<RootPathSample> MovedTowardLine(const std::vector<RootPathSample>& knots, long i, long j,
                                            const RunLine& line, double blend, double v_max) {
  std::vector<RootPathSample> moved(knots.begin() + i, knots.begin() + j + 1);
  for (std::size_t m = 1; m + 1 < moved.size(); ++m) {
    moved[m].p.head<2>() += blend * (line.on_line[m] - moved[m].p.head<2>());
    const Eigen::Vector2d v = moved[m].v.head<2>();
    const Eigen::Vector2d heading = v.norm() > 1e-9 ? v.normalized() : line.dir;
    const Eigen::Vector2d turned = (1.0 - blend) * heading + blend * line.dir;
    if (turned.norm() > 1e-9) {
      moved[m].v.head<2>() = (v.norm() * turned.normalized()).cwiseMax(-v_max).cwiseMin(v_max);
    }
  }
  return moved;
}

// The pieces steered between consecutive moved knots and their total duration.
struct SteeredRun {
  std::vector<RootSegment> pieces;
  double duration = 0.0;  // [s]
};

// Steers between consecutive knots; nullopt as soon as one piece cannot be steered.
std::optional<SteeredRun> SteerRun(const detail::KinodynamicMotionValidator& validator,
                                   const std::vector<RootPathSample>& knots) {
  SteeredRun run;
  for (std::size_t m = 0; m + 1 < knots.size(); ++m) {
    auto piece = validator.Steer(PointState{knots[m].p, knots[m].v}, knots[m].rest_yaw,
                                 PointState{knots[m + 1].p, knots[m + 1].v}, knots[m + 1].rest_yaw);
    if (!piece) return std::nullopt;
    run.duration += piece->Duration();
    run.pieces.push_back(*piece);
  }
  return run;
}

RootPath Straighten(const RootPath& path, const detail::KinodynamicMotionValidator& validator, int iterations,
                    double knot_spacing, double max_duration, std::uint64_t seed,
                    const ompl::base::PlannerTerminationCondition& ptc) {
  const double h = validator.Settings().time_step;
  const double T = path.Duration();
  const double spacing = h * std::max(1.0, std::round(knot_spacing / h));
  std::vector<RootPathSample> knots = Knots(path, spacing);
  const long n = static_cast<long>(knots.size()) - 1;
  if (iterations <= 0 || n < 2) return path;
  std::vector<RootPath> pieces = PiecesBetween(path, knots);
  const double v_max = validator.Settings().limits.horizontal.v_max;
  // Each run may take one time step per piece longer; the whole path at most max_duration.
  double total = T;
  const double max_total = std::max(T, max_duration);
  std::mt19937_64 rng(seed);
  for (int it = 0; it < iterations && !ptc(); ++it) {
    long i = 0;
    long j = n;
    if (it > 0) {
      i = std::uniform_int_distribution<long>(0, n - 2)(rng);
      j = std::uniform_int_distribution<long>(i + 2, n)(rng);
    }
    const std::optional<RunLine> line = LineOfRun(knots, i, j);
    if (!line || line->deviation < kStraightTolerance) continue;  // a loop, or already straight
    double old_duration = 0.0;
    for (long k = i; k < j; ++k) old_duration += pieces[static_cast<std::size_t>(k)].Duration();
    for (const double blend : {1.0, 0.5}) {
      const std::vector<RootPathSample> moved = MovedTowardLine(knots, i, j, *line, blend, v_max);
      const std::optional<SteeredRun> steered = SteerRun(validator, moved);
      // Steered durations are rounded up to the time grid: up to one step per piece longer.
      const double allowed = old_duration + h * static_cast<double>(j - i) + 1e-9;
      if (!steered || steered->duration > allowed || total - old_duration + steered->duration > max_total) continue;
      if (!std::all_of(steered->pieces.begin(), steered->pieces.end(),
                       [&](const RootSegment& s) { return validator.IsValid(s); })) {
        continue;
      }
      total += steered->duration - old_duration;
      for (std::size_t m = 0; m < steered->pieces.size(); ++m) {
        knots[static_cast<std::size_t>(i) + m] = moved[m];
        RootPath piece(path.Yaw());
        piece.Append(steered->pieces[m]);
        pieces[static_cast<std::size_t>(i) + m] = std::move(piece);
      }
      break;
    }
  }
  RootPath straight(path.Yaw());
  for (const RootPath& piece : pieces) {
    for (const auto& segment : piece.Segments()) straight.Append(segment);
  }
  return straight;
}

// Why a query ends before (or without) a path: its status and the reason given with it.
struct PlanFailure {
  RootPlanStatus status;
  std::string reason;
};

// The ends of a query as the search sees them: the goal at rest (at the start's height when the
// vertical axis is fixed) and the rest yaws of both ends.
struct PlanEnds {
  PointState start;
  PointState goal;
  double rest_start = 0.0;  // [rad] the rest yaw that gives the start's yaw at its velocity
  double rest_goal = 0.0;   // [rad]

  // The goal is the start and the base is at rest there: the path only turns on the spot.
  bool AtStart() const { return (goal.p - start.p).norm() < 1e-6 && start.v.norm() < 1e-9; }

  // A measured start where the reachability condition fails: the path joins it (at rest) to
  // `start`, the nearest state where it holds (RootPlanRequest::start_is_measured).
  std::optional<Eigen::Vector3d> joined_from;
};

PlanEnds EndsOf(const RootPlannerConfig& config, const RootPlanRequest& request) {
  PlanEnds ends;
  ends.start = request.start;
  ends.goal = PointState{request.goal, Eigen::Vector3d::Zero()};
  if (config.limits.VerticalFixed()) ends.goal.p.z() = ends.start.p.z();
  ends.rest_start = RestYawFor(config.yaw, ends.start.v, request.start_yaw);
  ends.rest_goal = WrapAngle(request.goal_yaw);
  return ends;
}

// A start velocity beyond the limits (any vertical velocity when the vertical axis is fixed).
std::optional<PlanFailure> StartVelocityProblem(const KinodynamicLimits& limits, const PointState& start) {
  for (int i = 0; i < 3; ++i) {
    const double v_max = limits.VerticalFixed() && i == 2 ? 0.0 : limits.Axis(i).v_max;
    if (std::abs(start.v[i]) > v_max + 1e-9) {
      return PlanFailure{RootPlanStatus::kStartInvalid, "start velocity " + ConfigNumber(start.v[i]) + " m/s along axis " +
                                                            std::to_string(i) + " exceeds the bound " + ConfigNumber(v_max) +
                                                            " m/s"};
    }
  }
  return std::nullopt;
}

// A start whose trunk volume touches the terrain (a robot standing a little lower than the
// reachability condition's conservative trunk allows, say on stairs) begins its path at the
// lowest height at most this much above it, in centimetre steps, where the condition holds.
constexpr double kStartRaiseM = 0.05;

// Where a measured start's joining move may end: on rings kStartJoinStepM apart up to
// kMaxStartJoinM, in 8 headings from `yaw` (ahead first, then alternately left and right), at
// heights kStartJoinStepM apart from two steps below to four above (the start's height only when
// the vertical axis is fixed); the nearest first.
constexpr double kStartJoinStepM = 0.05;

std::vector<Eigen::Vector3d> StartJoinCandidates(const Eigen::Vector3d& start, double yaw, bool vertical_fixed) {
  std::vector<std::pair<double, Eigen::Vector3d>> candidates;
  const int rings = static_cast<int>(std::lround(kMaxStartJoinM / kStartJoinStepM));
  const std::array<int, 8> headings{0, 1, -1, 2, -2, 3, -3, 4};
  for (int dz = vertical_fixed ? 0 : -2; dz <= (vertical_fixed ? 0 : 4); ++dz) {
    for (int ring = 0; ring <= rings; ++ring) {
      for (int k : headings) {
        const double a = yaw + k * M_PI / 4.0;
        const Eigen::Vector3d offset(ring * kStartJoinStepM * std::cos(a), ring * kStartJoinStepM * std::sin(a),
                                     dz * kStartJoinStepM);
        if (offset.norm() > kMaxStartJoinM + 1e-9) break;
        candidates.emplace_back(offset.norm(), start + offset);
        if (ring == 0) break;  // one candidate at the start's xy
      }
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first - 1e-9; });
  std::vector<Eigen::Vector3d> points;
  for (const auto& c : candidates) points.push_back(c.second);
  return points;
}

// Checks before any search: the start (raised as above; a measured one joined to the nearest
// state where the condition holds) and the goal satisfy the reachability condition, and a chain
// of contact surfaces joins the surfaces in reach at the start to those at the goal.
std::optional<PlanFailure> EndsProblem(const RootPlannerConfig& config, const std::vector<AffordanceSurface>& surfaces,
                                       bool start_is_measured, PlanEnds& ends, ReachabilityChecker& checker) {
  const double start_yaw = config.yaw.Yaw(ends.start.v.head<2>(), ends.rest_start);
  ReachabilityReport start_report = checker.Check(ends.start.p, start_yaw);
  for (int cm = 1; start_report.trunk_collision && cm <= std::lround(kStartRaiseM * 100); ++cm) {
    const Eigen::Vector3d raised = ends.start.p + Eigen::Vector3d(0, 0, 0.01 * cm);
    const ReachabilityReport report = checker.Check(raised, start_yaw);
    if (!report.Valid()) continue;
    ends.start.p = raised;
    if (config.limits.VerticalFixed()) ends.goal.p.z() = raised.z();
    start_report = report;
  }
  if (!start_report.Valid() && start_is_measured && ends.start.v.norm() < 1e-9) {
    for (const Eigen::Vector3d& p : StartJoinCandidates(ends.start.p, start_yaw, config.limits.VerticalFixed())) {
      const ReachabilityReport report = checker.Check(p, start_yaw);
      if (!report.Valid()) continue;
      ends.joined_from = ends.start.p;
      ends.start.p = p;
      start_report = report;
      break;
    }
  }
  if (!start_report.Valid()) return PlanFailure{RootPlanStatus::kStartInvalid, "start: " + start_report.Reason()};
  const ReachabilityReport goal_report = checker.Check(ends.goal.p, ends.rest_goal);
  if (!goal_report.Valid()) return PlanFailure{RootPlanStatus::kGoalInvalid, "goal: " + goal_report.Reason()};
  const std::vector<int> from(start_report.leg_surface.begin(), start_report.leg_surface.end());
  const std::vector<int> to(goal_report.leg_surface.begin(), goal_report.leg_surface.end());
  const SurfaceGraph graph(surfaces, config.max_surface_gap);
  if (graph.Joined(from, to)) return std::nullopt;
  return PlanFailure{RootPlanStatus::kGoalUnreachable,
                     "no chain of contact surfaces, each within " + ConfigNumber(config.max_surface_gap) +
                         " m of the next, joins the start's surfaces to the goal's (" +
                         std::to_string(graph.ComponentCount()) + " separate groups of surfaces)"};
}

// `path` after the straight move at rest from a measured start to where the search started.
RootPath WithStartJoin(const RootPlannerConfig& config, const PlanEnds& ends, const RootPath& path) {
  if (!ends.joined_from) return path;
  const std::optional<DoubleIntegratorTrajectory> join =
      Steer(PointState{*ends.joined_from, Eigen::Vector3d::Zero()}, PointState{ends.start.p, Eigen::Vector3d::Zero()},
            config.limits, config.time_step);
  RBCP_CHECK(join.has_value(), "a move between two states at rest steers");
  RootPath joined(config.yaw);
  joined.Append(RootSegment::Whole(*join, ends.rest_start, ends.rest_start));
  for (const RootSegment& segment : path.Segments()) joined.Append(segment);
  return joined;
}

// A goal at the start: the base stays where it is while its heading turns from the start's rest
// yaw to the goal's at kTurnOnTheSpotRate, the duration on the time grid.
RootPath TurnOnTheSpot(const RootPlannerConfig& config, const PlanEnds& ends) {
  const double turn = std::abs(WrapAngle(ends.rest_goal - ends.rest_start));
  const double duration = config.time_step * std::max(1.0, std::ceil(turn / kTurnOnTheSpotRate / config.time_step));
  std::array<AxisProfile, 3> axes;
  for (int i = 0; i < 3; ++i) axes[static_cast<std::size_t>(i)] = AxisProfile::Rest(ends.start.p[i], duration);
  RootPath path(config.yaw);
  path.Append(RootSegment::Whole(DoubleIntegratorTrajectory(axes, duration), ends.rest_start, ends.rest_goal));
  return path;
}

// The first heading of a turn on the spot (at every validation sample) that violates the
// reachability condition.
std::optional<PlanFailure> TurnProblem(const RootPlannerConfig& config, const RootPath& turn,
                                       ReachabilityChecker& checker) {
  for (const RootPathSample& s : turn.SampleEvery(config.time_step / config.validation_substeps)) {
    const ReachabilityReport report = checker.Check(s.p, s.yaw);
    if (!report.Valid()) {
      return PlanFailure{RootPlanStatus::kGoalInvalid,
                         "turning on the spot, at heading " + ConfigNumber(s.yaw) + " rad: " + report.Reason()};
    }
  }
  return std::nullopt;
}

// The OMPL objects of one search, made in this order (the state space, its information with the
// validity checker and motion validator, the problem, the planner), which they depend on.
struct SearchProblem {
  std::shared_ptr<ompl::base::SpaceInformation> si;
  std::shared_ptr<detail::ReachabilityValidityChecker> validity;
  std::shared_ptr<detail::KinodynamicMotionValidator> validator;
  std::shared_ptr<ompl::base::ProblemDefinition> pdef;
  std::shared_ptr<detail::KinodynamicBiRrt> planner;
};

// The state space's position bounds: they cover the surfaces (raised to standing height plus the
// sampler's height offsets), the start and the goal, with a margin.
std::pair<Eigen::Vector3d, Eigen::Vector3d> PositionBounds(const RootPlannerConfig& config, double standing_height,
                                                           const std::vector<AffordanceSurface>& surfaces,
                                                           const PlanEnds& ends) {
  Eigen::Vector3d lo = ends.start.p.cwiseMin(ends.goal.p);
  Eigen::Vector3d hi = ends.start.p.cwiseMax(ends.goal.p);
  for (const auto& s : surfaces) {
    for (const auto& v : s.vertices) {
      const Eigen::Vector3d raised = v + Eigen::Vector3d(0.0, 0.0, standing_height);
      lo = lo.cwiseMin(raised + Eigen::Vector3d(0.0, 0.0, config.sampler.height_offset[0]));
      hi = hi.cwiseMax(raised + Eigen::Vector3d(0.0, 0.0, config.sampler.height_offset[1]));
    }
  }
  lo -= Eigen::Vector3d::Constant(config.sampler.bounds_margin);
  hi += Eigen::Vector3d::Constant(config.sampler.bounds_margin);
  return {lo, hi};
}

// The sampler's settings: the config's, with the start's rest yaw and (vertical axis fixed) height.
detail::SamplerSettings SamplerSettingsOf(const RootPlannerConfig& config, double standing_height, const PlanEnds& ends) {
  detail::SamplerSettings sampler;
  sampler.standing_height = standing_height;
  sampler.area_weighted_probability = config.sampler.area_weighted_probability;
  sampler.height_offset_min = config.sampler.height_offset[0];
  sampler.height_offset_max = config.sampler.height_offset[1];
  sampler.zero_velocity_probability = config.sampler.zero_velocity_probability;
  sampler.attempts = config.sampler.attempts;
  sampler.repair_moves = config.sampler.repair_moves;
  sampler.repair_step = config.sampler.repair_step;
  sampler.rest_yaw = ends.rest_start;
  sampler.vertical_fixed = config.limits.VerticalFixed();
  sampler.fixed_height = ends.start.p.z();
  return sampler;
}

// The search from the start to the goal (reached exactly, at rest) over the reachable states.
// `checker` and `surfaces` must outlive the problem.
SearchProblem MakeSearchProblem(const RootPlannerConfig& config, double standing_height,
                                const std::vector<AffordanceSurface>& surfaces, ReachabilityChecker& checker,
                                const PlanEnds& ends, unsigned seed, int max_iterations) {
  namespace ob = ompl::base;
  SearchProblem problem;
  const auto [lo, hi] = PositionBounds(config, standing_height, surfaces, ends);
  auto space = std::make_shared<detail::RootStateSpace>(config.limits);
  space->SetPositionBounds(lo, hi);
  problem.si = std::make_shared<ob::SpaceInformation>(space);
  problem.validity = std::make_shared<detail::ReachabilityValidityChecker>(problem.si, &checker, config.yaw);
  problem.si->setStateValidityChecker(problem.validity);
  detail::SteeringSettings steering{config.limits, config.yaw, config.time_step, config.validation_substeps,
                                    config.max_piece_duration, config.max_yaw_rate};
  problem.validator = std::make_shared<detail::KinodynamicMotionValidator>(problem.si, problem.validity.get(), steering);
  problem.si->setMotionValidator(problem.validator);
  problem.si->setup();

  problem.pdef = std::make_shared<ob::ProblemDefinition>(problem.si);
  ob::ScopedState<> start_state(problem.si);
  detail::RootStateSpace::Set(start_state.get(), ends.start, ends.rest_start);
  ob::ScopedState<> goal_state(problem.si);
  detail::RootStateSpace::Set(goal_state.get(), ends.goal, ends.rest_goal);
  problem.pdef->addStartState(start_state);
  auto goal_region = std::make_shared<ob::GoalState>(problem.si);
  goal_region->setState(goal_state);
  goal_region->setThreshold(1e-6);
  problem.pdef->setGoal(goal_region);

  problem.planner = std::make_shared<detail::KinodynamicBiRrt>(problem.si, problem.validator.get(),
                                                               SamplerSettingsOf(config, standing_height, ends),
                                                               &surfaces, problem.validity.get(), &checker, seed);
  problem.planner->setProblemDefinition(problem.pdef);
  problem.planner->setup();
  problem.planner->SetMaxIterations(max_iterations);
  return problem;
}

// Runs the search and records its time and counters in `result`; a timeout when it finds no path
// (within max_iterations or the time budget).
std::optional<PlanFailure> Search(const SearchProblem& problem, int max_iterations, const RootPlanRequest& request,
                                  const ompl::base::PlannerTerminationCondition& ptc, RootPlanResult& result) {
  const Clock::time_point search_start = Clock::now();
  const ompl::base::PlannerStatus status = problem.planner->solve(ptc);
  result.search_time_s = Seconds(search_start);
  result.iterations = problem.planner->Stats().iterations;
  result.tree_states = problem.planner->Stats().start_tree_states + problem.planner->Stats().goal_tree_states;
  if (status == ompl::base::PlannerStatus::EXACT_SOLUTION && problem.pdef->hasExactSolution()) return std::nullopt;
  const std::string within = result.iterations >= max_iterations
                                 ? std::to_string(max_iterations) + " iterations"
                                 : "the time budget of " + ConfigNumber(request.time_budget_s) + " s";
  return PlanFailure{RootPlanStatus::kTimeout, "no path found within " + within + " (" +
                                                   std::to_string(result.iterations) + " iterations, " +
                                                   std::to_string(result.tree_states) + " tree states)"};
}

// The found path smoothed: random shortcuts, then horizontal straightening, which may lengthen the
// shortcut path by kMaxStraightenGrowth but never beyond the found path. Both draw from seeds made
// from the request's.
RootPath Smooth(const RootPath& found, const detail::KinodynamicMotionValidator& validator,
                const RootPlannerConfig& config, unsigned seed, const ompl::base::PlannerTerminationCondition& ptc) {
  const std::uint64_t smoothing_seed = static_cast<std::uint64_t>(seed) * 0x9E3779B97F4A7C15ULL;
  const RootPath shortcut = Shortcut(found, validator, config.shortcut_iterations, smoothing_seed + 1, ptc);
  return Straighten(shortcut, validator, config.straighten_iterations, config.straighten_knot_spacing,
                    std::min(kMaxStraightenGrowth * shortcut.Duration(), found.Duration()), smoothing_seed + 2, ptc);
}

}  // namespace

std::string ToString(RootPlanStatus status) {
  switch (status) {
    case RootPlanStatus::kOk: return "ok";
    case RootPlanStatus::kInvalidInput: return "invalid_input";
    case RootPlanStatus::kStartInvalid: return "start_invalid";
    case RootPlanStatus::kGoalInvalid: return "goal_invalid";
    case RootPlanStatus::kGoalUnreachable: return "goal_unreachable";
    case RootPlanStatus::kTimeout: return "timeout";
  }
  return "unknown";
}

unsigned GuideSeed(unsigned seed, int k) {
  RBCP_CHECK(k >= 0, "guide " + std::to_string(k));
  // A large odd stride (unsigned arithmetic wraps): seed s's guides never meet seed s+1's first few.
  constexpr unsigned kStride = 1000003u;
  return seed + static_cast<unsigned>(k) * kStride;
}

RootPlannerConfig RootPlannerConfig::Load(const YamlMap& map, const std::string& config_dir) {
  RootPlannerConfig c = LoadConfig<RootPlannerConfig>(map);
  const std::string folder = (!c.rom_folder.empty() && c.rom_folder[0] == '/') ? c.rom_folder : config_dir + "/" + c.rom_folder;
  c.roms = LoadRoms(folder);
  return c;
}

RootPlannerConfig RootPlannerConfig::LoadFile(const std::string& path, const std::string& config_dir) {
  return Load(YamlMap::LoadFile(path), config_dir);
}

RootPlanner::RootPlanner(const RobotModel& robot, RootPlannerConfig config)
    : config_(std::move(config)), nominal_base_height_(robot.NominalBaseHeight()) {
  config_.Validate("root planner config");
  for (const auto& rom : config_.roms) {
    if (rom.triangles.size() < 4) throw InputError("root planner config: expected four leg ROMs, got an empty shape");
  }
  trunk_ = MakeTrunkShape(config_.trunk);
}

std::optional<Eigen::Vector3d> RootPlanner::StandingPosition(const TriangleMesh& terrain, const Eigen::Vector2d& xy) const {
  const std::optional<double> height = TerrainHeightAt(terrain, xy);
  if (!height) return std::nullopt;
  return Eigen::Vector3d(xy.x(), xy.y(), *height + nominal_base_height_);
}

std::string MeasuredBaseProblem::Describe() const {
  if (kind == Kind::kNoTerrain) return "no terrain under the measured base";
  return "the measured base at (" + FixedNumber(base_W.x(), 2) + ", " + FixedNumber(base_W.y(), 2) + ", " +
         FixedNumber(base_W.z(), 2) + ") is inside the terrain, which rises to z " + FixedNumber(terrain_top_z, 2) +
         " there";
}

std::optional<MeasuredBaseProblem> RootPlanner::CheckMeasuredBase(const TriangleMesh& terrain,
                                                                  const Eigen::Vector3d& base_W) const {
  const std::optional<double> height = TerrainHeightAt(terrain, base_W.head<2>());
  if (!height) return MeasuredBaseProblem{MeasuredBaseProblem::Kind::kNoTerrain, base_W};
  if (*height <= base_W.z()) return std::nullopt;
  return MeasuredBaseProblem{MeasuredBaseProblem::Kind::kInsideTerrain, base_W, *height};
}

namespace {

/// Points on a grid of `spacing` over the contact surfaces' bounding box, with their distance to
/// `goal_xy`, the nearest first (ties in x, then y order: deterministic).
std::vector<std::pair<double, Eigen::Vector2d>> GridNearestTo(const std::vector<AffordanceSurface>& surfaces,
                                                              double spacing, const Eigen::Vector2d& goal_xy) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const AffordanceSurface& surface : surfaces) {
    for (const Eigen::Vector3d& v : surface.vertices) {
      lo = lo.cwiseMin(v.head<2>());
      hi = hi.cwiseMax(v.head<2>());
    }
  }
  std::vector<std::pair<double, Eigen::Vector2d>> points;
  for (double y = std::ceil(lo.y() / spacing) * spacing; y <= hi.y(); y += spacing) {
    for (double x = std::ceil(lo.x() / spacing) * spacing; x <= hi.x(); x += spacing) {
      const Eigen::Vector2d xy(x, y);
      points.emplace_back((goal_xy - xy).norm(), xy);
    }
  }
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : std::tie(a.second.x(), a.second.y()) < std::tie(b.second.x(), b.second.y());
  });
  return points;
}

/// Whether `xy` lies within `distance` of one of `places` (their xy: 2D or 3D points).
template <typename Point>
bool NearAny(const Eigen::Vector2d& xy, const std::vector<Point>& places, double distance) {
  return std::any_of(places.begin(), places.end(),
                     [&](const Point& p) { return (p.template head<2>() - xy).norm() < distance; });
}

}  // namespace

std::vector<Eigen::Vector3d> RootPlanner::GoalsToward(const TriangleMesh& terrain,
                                                     const std::vector<AffordanceSurface>& surfaces,
                                                     const Eigen::Vector2d& start_xy, const Eigen::Vector2d& goal_xy,
                                                     double goal_yaw, const GoalsTowardOptions& options,
                                                     const std::vector<Eigen::Vector2d>& dead_ends) const {
  if (!(options.spacing_m > 0.0) || !start_xy.allFinite() || !goal_xy.allFinite() || options.max_goals < 1) {
    throw InputError("GoalsToward: expected finite ends, a positive spacing and max_goals >= 1");
  }
  std::vector<Eigen::Vector3d> goals;
  if (surfaces.empty() || terrain.Empty()) return goals;
  ReachabilityChecker checker = MakeChecker(terrain, surfaces);
  const TerrainHeightMap heights(terrain);
  const auto standing = [&](const Eigen::Vector2d& xy) -> std::optional<Eigen::Vector3d> {
    const std::optional<double> z = heights.At(xy);
    if (!z) return std::nullopt;
    return Eigen::Vector3d(xy.x(), xy.y(), *z + nominal_base_height_);
  };
  // A candidate the robot can walk to: some surface in reach of it joined to one under the start.
  const SurfaceGraph graph(surfaces, config_.max_surface_gap);
  std::vector<int> at_start;
  if (const std::optional<double> z = heights.At(start_xy)) {
    at_start = graph.SurfacesNear(Eigen::Vector3d(start_xy.x(), start_xy.y(), *z), options.start_surfaces_m);
  }
  const auto reachable_goal = [&](const Eigen::Vector3d& p, double yaw) {
    const ReachabilityReport report = checker.Check(p, yaw);
    return report.Valid() && graph.Joined(at_start, std::vector<int>(report.leg_surface.begin(), report.leg_surface.end()));
  };
  if (const auto at_goal = standing(goal_xy); at_goal && reachable_goal(*at_goal, goal_yaw)) {
    goals.push_back(*at_goal);
  }
  // Candidates on a grid over the contact surfaces, the nearest to the goal first, each facing the
  // goal with known terrain ahead of it for the front feet.
  const double from_start = (goal_xy - start_xy).norm();
  int evaluated = 0;
  for (const auto& [left, xy] : GridNearestTo(surfaces, options.spacing_m, goal_xy)) {
    if (static_cast<int>(goals.size()) >= options.max_goals || evaluated >= options.max_evaluations) break;
    if (from_start - left < options.min_progress_m || left <= 1e-9 || NearAny(xy, dead_ends, options.visited_m)) continue;
    const Eigen::Vector2d toward = (goal_xy - xy) / left;
    const std::optional<Eigen::Vector3d> p = standing(xy);
    if (!p || !heights.At(xy + options.ahead_m * toward)) continue;
    ++evaluated;
    // Apart from the goals taken already: the next try is somewhere else.
    if (NearAny(xy, goals, options.apart_m)) continue;
    if (reachable_goal(*p, std::atan2(toward.y(), toward.x()))) goals.push_back(*p);
  }
  return goals;
}

std::vector<Eigen::Vector3d> RootPlanner::FrontierGoals(const TriangleMesh& terrain,
                                                       const std::vector<AffordanceSurface>& surfaces,
                                                       const Eigen::Vector2d& goal_xy,
                                                       const std::vector<Eigen::Vector2d>& visited,
                                                       const GoalsTowardOptions& options) const {
  if (!(options.spacing_m > 0.0) || !(options.frontier_m > 0.0) || !goal_xy.allFinite() || options.max_goals < 1) {
    throw InputError("FrontierGoals: expected a finite goal, a positive spacing and frontier and max_goals >= 1");
  }
  std::vector<Eigen::Vector3d> goals;
  if (surfaces.empty() || terrain.Empty()) return goals;
  ReachabilityChecker checker = MakeChecker(terrain, surfaces);
  const TerrainHeightMap heights(terrain);
  // Unknown terrain within frontier_m: some of 8 directions finds none there.
  const auto at_frontier = [&](const Eigen::Vector2d& xy) {
    for (int k = 0; k < 8; ++k) {
      const double a = k * M_PI / 4.0;
      if (!heights.At(xy + options.frontier_m * Eigen::Vector2d(std::cos(a), std::sin(a)))) return true;
    }
    return false;
  };
  int evaluated = 0;
  for (const auto& [left, xy] : GridNearestTo(surfaces, options.spacing_m, goal_xy)) {
    if (static_cast<int>(goals.size()) >= options.max_goals || evaluated >= options.max_evaluations) break;
    if (left <= 1e-9 || NearAny(xy, visited, options.visited_m) || NearAny(xy, goals, options.apart_m)) continue;
    const std::optional<double> z = heights.At(xy);
    if (!z || !at_frontier(xy)) continue;
    ++evaluated;
    const Eigen::Vector2d toward = (goal_xy - xy) / left;
    const Eigen::Vector3d p(xy.x(), xy.y(), *z + nominal_base_height_);
    if (checker.IsValid(p, std::atan2(toward.y(), toward.x()))) goals.push_back(p);
  }
  return goals;
}

ReachabilityChecker RootPlanner::MakeChecker(const TriangleMesh& terrain,
                                             const std::vector<AffordanceSurface>& surfaces) const {
  return ReachabilityChecker(terrain, surfaces, config_.roms, trunk_, config_.surface_depth);
}

RootPlanResult RootPlanner::Plan(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                                 const Eigen::Vector3d& start_W, double start_yaw, const Eigen::Vector3d& goal_W,
                                 double goal_yaw, unsigned seed, double time_budget_s) const {
  RootPlanRequest request;
  request.start.p = start_W;
  request.start_yaw = start_yaw;
  request.goal = goal_W;
  request.goal_yaw = goal_yaw;
  request.seed = seed;
  request.time_budget_s = time_budget_s;
  return Plan(terrain, surfaces, request);
}

RootPlanResult RootPlanner::Plan(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                                 const RootPlanRequest& request) const {
  namespace ob = ompl::base;
  const Clock::time_point t0 = Clock::now();
  RootPlanResult result;
  auto done = [&](RootPlanStatus status, std::string reason) {
    result.status = status;
    result.reason = std::move(reason);
    result.planning_time_s = Seconds(t0);
    return result;
  };
  if (!request.start.p.allFinite() || !request.start.v.allFinite() || !request.goal.allFinite() ||
      !std::isfinite(request.start_yaw) || !std::isfinite(request.goal_yaw)) {
    return done(RootPlanStatus::kInvalidInput,
                "root plan request: expected finite start and goal, got a non-finite value");
  }
  if (!(request.time_budget_s > 0.0)) {
    return done(RootPlanStatus::kInvalidInput,
                "root plan request: expected a time budget > 0 s, got " + ConfigNumber(request.time_budget_s));
  }

  // Checks of the ends, cheapest first.
  PlanEnds ends = EndsOf(config_, request);
  if (auto failure = StartVelocityProblem(config_.limits, ends.start)) return done(failure->status, failure->reason);
  if (surfaces.empty()) return done(RootPlanStatus::kStartInvalid, "no contact surfaces");
  ReachabilityChecker checker = MakeChecker(terrain, surfaces);
  if (auto failure = EndsProblem(config_, surfaces, request.start_is_measured, ends, checker)) {
    return done(failure->status, failure->reason);
  }
  if (ends.joined_from) result.start_join_m = (ends.start.p - *ends.joined_from).norm();

  if (ends.AtStart()) {
    const RootPath turn = TurnOnTheSpot(config_, ends);
    if (auto failure = TurnProblem(config_, turn, checker)) return done(failure->status, failure->reason);
    result.path = WithStartJoin(config_, ends, turn);
    result.samples = result.path.SampleEvery(config_.time_step);
    result.validity_checks = checker.Queries();
    return done(RootPlanStatus::kOk, "");
  }

  // The search, in what is left of the time budget.
  const int max_iterations =
      request.max_iterations > 0 ? std::min(request.max_iterations, config_.max_iterations) : config_.max_iterations;
  const SearchProblem problem =
      MakeSearchProblem(config_, nominal_base_height_, surfaces, checker, ends, request.seed, max_iterations);
  const double remaining = request.time_budget_s - Seconds(t0);
  const ob::PlannerTerminationCondition ptc = ob::timedPlannerTerminationCondition(std::max(0.0, remaining));
  if (auto failure = Search(problem, max_iterations, request, ptc, result)) {
    result.validity_checks = checker.Queries();
    return done(failure->status, failure->reason);
  }

  const RootPath& found = problem.pdef->getSolutionPath()->as<detail::RootTrajectoryPath>()->Path();
  result.duration_before_shortcut_s = found.Duration();
  result.path = WithStartJoin(config_, ends, Smooth(found, *problem.validator, config_, request.seed, ptc));
  result.validity_checks = checker.Queries();
  if (ptc()) {
    // Cut short, the smoothing would give a path that depends on the machine's load.
    result.path = RootPath();
    return done(RootPlanStatus::kTimeout,
                "the time budget of " + ConfigNumber(request.time_budget_s) + " s ran out while smoothing the path");
  }
  result.samples = result.path.SampleEvery(config_.time_step);
  return done(RootPlanStatus::kOk, "");
}

}  // namespace rbcp
