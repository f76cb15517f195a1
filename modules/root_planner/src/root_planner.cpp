#include "rbcp/root_planner/root_planner.h"

#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/goals/GoalState.h>

#include <chrono>
#include <cmath>
#include <limits>
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

RootPath Straighten(const RootPath& path, const detail::KinodynamicMotionValidator& validator, int iterations,
                    double knot_spacing, double max_duration, std::uint64_t seed,
                    const ompl::base::PlannerTerminationCondition& ptc) {
  const double h = validator.Settings().time_step;
  const double T = path.Duration();
  const double spacing = h * std::max(1.0, std::round(knot_spacing / h));
  std::vector<RootPathSample> knots;
  for (double t = 0.0; t < T - 0.5 * spacing; t += spacing) knots.push_back(path.Sample(t));
  knots.push_back(path.Sample(T));
  const long n = static_cast<long>(knots.size()) - 1;
  if (iterations <= 0 || n < 2) return path;
  std::vector<RootPath> pieces;
  for (long k = 0; k < n; ++k) {
    pieces.push_back(path.Part(knots[static_cast<std::size_t>(k)].t, knots[static_cast<std::size_t>(k + 1)].t));
  }
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
    const Eigen::Vector2d A = knots[static_cast<std::size_t>(i)].p.head<2>();
    const Eigen::Vector2d B = knots[static_cast<std::size_t>(j)].p.head<2>();
    if ((B - A).norm() < 1e-6) continue;
    const Eigen::Vector2d dir = (B - A).normalized();
    // Each knot's point on the line, at its fraction of the run's horizontal length.
    std::vector<double> arc{0.0};
    for (long k = i + 1; k <= j; ++k) {
      arc.push_back(arc.back() + (knots[static_cast<std::size_t>(k)].p - knots[static_cast<std::size_t>(k - 1)].p).head<2>().norm());
    }
    std::vector<Eigen::Vector2d> on_line;
    double deviation = 0.0;
    for (long k = i; k <= j; ++k) {
      const std::size_t m = static_cast<std::size_t>(k - i);
      on_line.push_back(A + (arc[m] / arc.back()) * (B - A));
      deviation = std::max(deviation, (knots[static_cast<std::size_t>(k)].p.head<2>() - on_line.back()).norm());
    }
    if (deviation < kStraightTolerance) continue;  // already straight
    double old_duration = 0.0;
    for (long k = i; k < j; ++k) old_duration += pieces[static_cast<std::size_t>(k)].Duration();
    for (const double blend : {1.0, 0.5}) {
      std::vector<RootPathSample> moved(knots.begin() + i, knots.begin() + j + 1);
      for (std::size_t m = 1; m + 1 < moved.size(); ++m) {
        moved[m].p.head<2>() += blend * (on_line[m] - moved[m].p.head<2>());
        const Eigen::Vector2d v = moved[m].v.head<2>();
        const Eigen::Vector2d heading = v.norm() > 1e-9 ? v.normalized() : dir;
        const Eigen::Vector2d turned = (1.0 - blend) * heading + blend * dir;
        if (turned.norm() > 1e-9) {
          moved[m].v.head<2>() = (v.norm() * turned.normalized()).cwiseMax(-v_max).cwiseMin(v_max);
        }
      }
      std::vector<RootSegment> steered;
      double duration = 0.0;
      bool ok = true;
      for (std::size_t m = 0; ok && m + 1 < moved.size(); ++m) {
        auto piece = validator.Steer(PointState{moved[m].p, moved[m].v}, moved[m].rest_yaw,
                                     PointState{moved[m + 1].p, moved[m + 1].v}, moved[m + 1].rest_yaw);
        ok = piece.has_value();
        if (ok) {
          duration += piece->Duration();
          steered.push_back(*piece);
        }
      }
      // Steered durations are rounded up to the time grid: up to one step per piece longer.
      const double allowed = old_duration + h * static_cast<double>(j - i) + 1e-9;
      if (!ok || duration > allowed || total - old_duration + duration > max_total) continue;
      if (!std::all_of(steered.begin(), steered.end(), [&](const RootSegment& s) { return validator.IsValid(s); })) {
        continue;
      }
      total += duration - old_duration;
      for (std::size_t m = 0; m < steered.size(); ++m) {
        knots[static_cast<std::size_t>(i) + m] = moved[m];
        RootPath piece(path.Yaw());
        piece.Append(steered[m]);
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

}  // namespace

std::string ToString(RootPlanStatus status) {
  switch (status) {
    case RootPlanStatus::kOk: return "ok";
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

std::string RootPlanner::MeasuredBaseProblem(const TriangleMesh& terrain, const Eigen::Vector3d& base_W) const {
  const std::optional<double> height = TerrainHeightAt(terrain, base_W.head<2>());
  if (!height) return "no terrain under the measured base";
  if (*height <= base_W.z()) return "";
  return "the measured base at (" + FixedNumber(base_W.x(), 2) + ", " + FixedNumber(base_W.y(), 2) + ", " +
         FixedNumber(base_W.z(), 2) + ") is inside the terrain, which rises to z " + FixedNumber(*height, 2) + " there";
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
  if (!request.start.p.allFinite() || !request.start.v.allFinite() || !request.goal.allFinite() ||
      !std::isfinite(request.start_yaw) || !std::isfinite(request.goal_yaw)) {
    throw InputError("root plan request: expected finite start and goal, got a non-finite value");
  }
  if (!(request.time_budget_s > 0.0)) {
    throw InputError("root plan request: expected a time budget > 0 s, got " + ConfigNumber(request.time_budget_s));
  }
  RootPlanResult result;
  auto done = [&](RootPlanStatus status, std::string reason) {
    result.status = status;
    result.reason = std::move(reason);
    result.planning_time_s = Seconds(t0);
    return result;
  };

  const KinodynamicLimits& limits = config_.limits;
  PointState start = request.start;
  PointState goal{request.goal, Eigen::Vector3d::Zero()};
  if (limits.VerticalFixed()) goal.p.z() = start.p.z();
  for (int i = 0; i < 3; ++i) {
    const double v_max = limits.VerticalFixed() && i == 2 ? 0.0 : limits.Axis(i).v_max;
    if (std::abs(start.v[i]) > v_max + 1e-9) {
      return done(RootPlanStatus::kStartInvalid, "start velocity " + ConfigNumber(start.v[i]) + " m/s along axis " +
                                                     std::to_string(i) + " exceeds the bound " + ConfigNumber(v_max) + " m/s");
    }
  }
  if (surfaces.empty()) return done(RootPlanStatus::kStartInvalid, "no contact surfaces");

  ReachabilityChecker checker = MakeChecker(terrain, surfaces);
  const double rest_start = RestYawFor(config_.yaw, start.v, request.start_yaw);
  const double rest_goal = WrapAngle(request.goal_yaw);
  const ReachabilityReport start_report = checker.Check(start.p, config_.yaw.Yaw(start.v.head<2>(), rest_start));
  if (!start_report.Valid()) return done(RootPlanStatus::kStartInvalid, "start: " + start_report.Reason());
  const ReachabilityReport goal_report = checker.Check(goal.p, rest_goal);
  if (!goal_report.Valid()) return done(RootPlanStatus::kGoalInvalid, "goal: " + goal_report.Reason());
  {
    const std::vector<int> from(start_report.leg_surface.begin(), start_report.leg_surface.end());
    const std::vector<int> to(goal_report.leg_surface.begin(), goal_report.leg_surface.end());
    const SurfaceGraph graph(surfaces, config_.max_surface_gap);
    if (!graph.Joined(from, to)) {
      return done(RootPlanStatus::kGoalUnreachable,
                  "no chain of contact surfaces, each within " + ConfigNumber(config_.max_surface_gap) +
                      " m of the next, joins the start's surfaces to the goal's (" +
                      std::to_string(graph.ComponentCount()) + " separate groups of surfaces)");
    }
  }

  // A goal at the start: the base stays where it is and its heading turns to the goal's.
  if ((goal.p - start.p).norm() < 1e-6 && start.v.norm() < 1e-9) {
    const double turn = std::abs(WrapAngle(rest_goal - rest_start));
    const double duration =
        config_.time_step * std::max(1.0, std::ceil(turn / kTurnOnTheSpotRate / config_.time_step));
    std::array<AxisProfile, 3> axes;
    for (int i = 0; i < 3; ++i) axes[static_cast<std::size_t>(i)] = AxisProfile::Rest(start.p[i], duration);
    RootPath path(config_.yaw);
    path.Append(RootSegment::Whole(DoubleIntegratorTrajectory(axes, duration), rest_start, rest_goal));
    for (const RootPathSample& s : path.SampleEvery(config_.time_step / config_.validation_substeps)) {
      const ReachabilityReport report = checker.Check(s.p, s.yaw);
      if (!report.Valid()) {
        return done(RootPlanStatus::kGoalInvalid,
                    "turning on the spot, at heading " + ConfigNumber(s.yaw) + " rad: " + report.Reason());
      }
    }
    result.path = path;
    result.samples = path.SampleEvery(config_.time_step);
    result.validity_checks = checker.Queries();
    return done(RootPlanStatus::kOk, "");
  }

  // OMPL problem: the state space bounds cover the surfaces (raised to standing height), the
  // start and the goal, with a margin.
  Eigen::Vector3d lo = start.p.cwiseMin(goal.p);
  Eigen::Vector3d hi = start.p.cwiseMax(goal.p);
  for (const auto& s : surfaces) {
    for (const auto& v : s.vertices) {
      const Eigen::Vector3d raised = v + Eigen::Vector3d(0.0, 0.0, nominal_base_height_);
      lo = lo.cwiseMin(raised + Eigen::Vector3d(0.0, 0.0, config_.sampler.height_offset[0]));
      hi = hi.cwiseMax(raised + Eigen::Vector3d(0.0, 0.0, config_.sampler.height_offset[1]));
    }
  }
  lo -= Eigen::Vector3d::Constant(config_.sampler.bounds_margin);
  hi += Eigen::Vector3d::Constant(config_.sampler.bounds_margin);
  auto space = std::make_shared<detail::RootStateSpace>(limits);
  space->SetPositionBounds(lo, hi);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  auto validity = std::make_shared<detail::ReachabilityValidityChecker>(si, &checker, config_.yaw);
  si->setStateValidityChecker(validity);
  detail::SteeringSettings steering{limits, config_.yaw, config_.time_step, config_.validation_substeps,
                                    config_.max_piece_duration, config_.max_yaw_rate};
  auto validator = std::make_shared<detail::KinodynamicMotionValidator>(si, validity.get(), steering);
  si->setMotionValidator(validator);
  si->setup();

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start_state(si);
  detail::RootStateSpace::Set(start_state.get(), start, rest_start);
  ob::ScopedState<> goal_state(si);
  detail::RootStateSpace::Set(goal_state.get(), goal, rest_goal);
  pdef->addStartState(start_state);
  auto goal_region = std::make_shared<ob::GoalState>(si);
  goal_region->setState(goal_state);
  goal_region->setThreshold(1e-6);
  pdef->setGoal(goal_region);

  detail::SamplerSettings sampler;
  sampler.standing_height = nominal_base_height_;
  sampler.area_weighted_probability = config_.sampler.area_weighted_probability;
  sampler.height_offset_min = config_.sampler.height_offset[0];
  sampler.height_offset_max = config_.sampler.height_offset[1];
  sampler.zero_velocity_probability = config_.sampler.zero_velocity_probability;
  sampler.attempts = config_.sampler.attempts;
  sampler.repair_moves = config_.sampler.repair_moves;
  sampler.repair_step = config_.sampler.repair_step;
  sampler.rest_yaw = rest_start;
  sampler.vertical_fixed = limits.VerticalFixed();
  sampler.fixed_height = start.p.z();
  auto planner = std::make_shared<detail::KinodynamicBiRrt>(si, validator.get(), sampler, &surfaces, validity.get(),
                                                            &checker, request.seed);
  planner->setProblemDefinition(pdef);
  planner->setup();
  planner->SetMaxIterations(config_.max_iterations);

  const double remaining = request.time_budget_s - Seconds(t0);
  const ob::PlannerTerminationCondition ptc = ob::timedPlannerTerminationCondition(std::max(0.0, remaining));
  const Clock::time_point search_start = Clock::now();
  const ob::PlannerStatus status = planner->solve(ptc);
  result.search_time_s = Seconds(search_start);
  result.iterations = planner->Stats().iterations;
  result.tree_states = planner->Stats().start_tree_states + planner->Stats().goal_tree_states;
  if (status != ob::PlannerStatus::EXACT_SOLUTION || !pdef->hasExactSolution()) {
    result.validity_checks = checker.Queries();
    const std::string within = result.iterations >= config_.max_iterations
                                   ? std::to_string(config_.max_iterations) + " iterations"
                                   : "the time budget of " + ConfigNumber(request.time_budget_s) + " s";
    return done(RootPlanStatus::kTimeout, "no path found within " + within + " (" + std::to_string(result.iterations) +
                                              " iterations, " + std::to_string(result.tree_states) + " tree states)");
  }
  const auto* found = pdef->getSolutionPath()->as<detail::RootTrajectoryPath>();
  result.duration_before_shortcut_s = found->Path().Duration();
  const std::uint64_t smoothing_seed = static_cast<std::uint64_t>(request.seed) * 0x9E3779B97F4A7C15ULL;
  result.path = Shortcut(found->Path(), *validator, config_.shortcut_iterations, smoothing_seed + 1, ptc);
  result.path = Straighten(result.path, *validator, config_.straighten_iterations, config_.straighten_knot_spacing,
                           std::min(kMaxStraightenGrowth * result.path.Duration(), result.duration_before_shortcut_s),
                           smoothing_seed + 2, ptc);
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
