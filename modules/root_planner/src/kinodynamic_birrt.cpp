#include "kinodynamic_birrt.h"

#include <ompl/base/PlannerData.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/goals/GoalState.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/spaces/SO2StateSpace.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/core/angle.h"
#include "rbcp/core/error.h"

namespace rbcp::detail {
namespace {

const double* Values(const ob::State* state, unsigned index) {
  return state->as<ob::CompoundState>()->as<ob::RealVectorStateSpace::StateType>(index)->values;
}
double* Values(ob::State* state, unsigned index) {
  return state->as<ob::CompoundState>()->as<ob::RealVectorStateSpace::StateType>(index)->values;
}

constexpr double kTimeTolerance = 1e-9;  // [s]

}  // namespace

// ---- RootStateSpace -----------------------------------------------------------------------------

RootStateSpace::RootStateSpace(const KinodynamicLimits& limits) : limits_(limits) {
  setName("RootStateSpace");
  auto position = std::make_shared<ob::RealVectorStateSpace>(3);
  auto velocity = std::make_shared<ob::RealVectorStateSpace>(3);
  ob::RealVectorBounds vb(3);
  for (int i = 0; i < 3; ++i) {
    // A fixed vertical axis still needs a non-empty interval for OMPL.
    const double v = std::max(limits.Axis(i).v_max, 1e-9);
    vb.setLow(static_cast<unsigned>(i), -v);
    vb.setHigh(static_cast<unsigned>(i), v);
  }
  velocity->setBounds(vb);
  addSubspace(position, 1.0);
  addSubspace(velocity, 1.0);
  addSubspace(std::make_shared<ob::SO2StateSpace>(), 1.0);
  lock();
}

void RootStateSpace::SetPositionBounds(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  ob::RealVectorBounds b(3);
  for (unsigned i = 0; i < 3; ++i) {
    b.setLow(i, lo[static_cast<int>(i)]);
    b.setHigh(i, std::max(hi[static_cast<int>(i)], lo[static_cast<int>(i)] + 1e-9));
  }
  as<ob::RealVectorStateSpace>(0)->setBounds(b);
}

PointState RootStateSpace::Point(const ob::State* state) {
  const double* p = Values(state, 0);
  const double* v = Values(state, 1);
  PointState s;
  s.p = {p[0], p[1], p[2]};
  s.v = {v[0], v[1], v[2]};
  return s;
}

double RootStateSpace::RestYaw(const ob::State* state) {
  return state->as<ob::CompoundState>()->as<ob::SO2StateSpace::StateType>(2)->value;
}

void RootStateSpace::Set(ob::State* state, const PointState& point, double rest_yaw) {
  double* p = Values(state, 0);
  double* v = Values(state, 1);
  for (int i = 0; i < 3; ++i) {
    p[i] = point.p[i];
    v[i] = point.v[i];
  }
  state->as<ob::CompoundState>()->as<ob::SO2StateSpace::StateType>(2)->value = WrapAngle(rest_yaw);
}

double RootStateSpace::distance(const ob::State* from, const ob::State* to) const {
  return MinimumTimeBound(Point(from), Point(to), limits_);
}

// ---- Validity -------------------------------------------------------------------------------------

ReachabilityValidityChecker::ReachabilityValidityChecker(const ob::SpaceInformationPtr& si,
                                                         ReachabilityChecker* checker, YawModel yaw)
    : ob::StateValidityChecker(si), checker_(checker), yaw_(yaw) {}

bool ReachabilityValidityChecker::isValid(const ob::State* state) const {
  const PointState point = RootStateSpace::Point(state);
  return IsValid(point.p, point.v, RootStateSpace::RestYaw(state));
}

double ReachabilityValidityChecker::Yaw(const Eigen::Vector3d& v, double rest_yaw) const {
  return yaw_.Yaw(v.head<2>(), rest_yaw);
}

bool ReachabilityValidityChecker::IsValid(const Eigen::Vector3d& p, const Eigen::Vector3d& v, double rest_yaw) const {
  ++checks_;
  return checker_->IsValid(p, yaw_.Yaw(v.head<2>(), rest_yaw));
}

KinodynamicMotionValidator::KinodynamicMotionValidator(const ob::SpaceInformationPtr& si,
                                                       const ReachabilityValidityChecker* validity,
                                                       SteeringSettings settings)
    : ob::MotionValidator(si), validity_(validity), settings_(settings) {}

std::optional<RootSegment> KinodynamicMotionValidator::Steer(const PointState& from, double rest_from,
                                                             const PointState& to, double rest_to) const {
  auto trajectory = rbcp::Steer(from, to, settings_.limits, settings_.time_step);
  if (!trajectory || trajectory->Duration() > settings_.max_piece_duration) return std::nullopt;
  return RootSegment::Whole(*trajectory, rest_from, rest_to);
}

long KinodynamicMotionValidator::SampleCount(const RootSegment& segment) const {
  const double dt = settings_.time_step / settings_.validation_substeps;
  return std::lround(segment.Duration() / dt);
}

RootPathSample KinodynamicMotionValidator::SampleAt(const RootSegment& segment, long k) const {
  const long n = SampleCount(segment);
  const double t = k >= n ? segment.Duration() : static_cast<double>(k) * settings_.time_step / settings_.validation_substeps;
  return segment.Sample(t, settings_.yaw);
}

bool KinodynamicMotionValidator::Valid(const RootPathSample& s) const { return validity_->IsValid(s.p, s.v, s.rest_yaw); }

bool KinodynamicMotionValidator::YawStepValid(const RootPathSample& a, const RootPathSample& b) const {
  const double dt = std::abs(b.t - a.t);
  return std::abs(WrapAngle(b.yaw - a.yaw)) <= settings_.max_yaw_rate * dt + 1e-12;
}

double KinodynamicMotionValidator::ValidPrefix(const RootSegment& segment) const {
  const long n = SampleCount(segment);
  const long m = settings_.validation_substeps;
  RootPathSample previous = SampleAt(segment, 0);
  for (long k = 1; k <= n; ++k) {
    const RootPathSample s = SampleAt(segment, k);
    if (!YawStepValid(previous, s) || !Valid(s)) return static_cast<double>((k - 1) / m) * settings_.time_step;
    previous = s;
  }
  return segment.Duration();
}

double KinodynamicMotionValidator::ValidSuffix(const RootSegment& segment) const {
  const long n = SampleCount(segment);
  const long m = settings_.validation_substeps;
  RootPathSample next = SampleAt(segment, n);
  for (long k = n - 1; k >= 0; --k) {
    const RootPathSample s = SampleAt(segment, k);
    if (!YawStepValid(s, next) || !Valid(s)) {
      const long steps = (k + 1 + m - 1) / m;
      return std::min(segment.Duration(), static_cast<double>(steps) * settings_.time_step);
    }
    next = s;
  }
  return 0.0;
}

bool KinodynamicMotionValidator::IsValid(const RootSegment& segment) const {
  const long n = SampleCount(segment);
  RootPathSample previous = SampleAt(segment, 0);
  if (!Valid(previous)) return false;
  for (long k = 1; k <= n; ++k) {
    const RootPathSample s = SampleAt(segment, k);
    if (!YawStepValid(previous, s) || !Valid(s)) return false;
    previous = s;
  }
  return true;
}

bool KinodynamicMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2) const {
  auto segment = Steer(RootStateSpace::Point(s1), RootStateSpace::RestYaw(s1), RootStateSpace::Point(s2),
                       RootStateSpace::RestYaw(s2));
  if (!segment) {
    invalid_++;
    return false;
  }
  const bool ok = ValidPrefix(*segment) >= segment->Duration() - kTimeTolerance;
  ok ? valid_++ : invalid_++;
  return ok;
}

bool KinodynamicMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2,
                                             std::pair<ob::State*, double>& last_valid) const {
  auto segment = Steer(RootStateSpace::Point(s1), RootStateSpace::RestYaw(s1), RootStateSpace::Point(s2),
                       RootStateSpace::RestYaw(s2));
  if (!segment) {
    if (last_valid.first != nullptr) si_->copyState(last_valid.first, s1);
    last_valid.second = 0.0;
    invalid_++;
    return false;
  }
  const double prefix = ValidPrefix(*segment);
  const double duration = segment->Duration();
  if (prefix >= duration - kTimeTolerance) {
    valid_++;
    return true;
  }
  if (last_valid.first != nullptr) {
    const RootPathSample s = segment->Sample(prefix, settings_.yaw);
    RootStateSpace::Set(last_valid.first, PointState{s.p, s.v}, s.rest_yaw);
  }
  last_valid.second = duration > 0.0 ? prefix / duration : 0.0;
  invalid_++;
  return false;
}

// ---- Sampler --------------------------------------------------------------------------------------

SurfaceStateSampler::SurfaceStateSampler(const ob::StateSpace* space, const std::vector<AffordanceSurface>* surfaces,
                                         const ReachabilityValidityChecker* validity, ReachabilityChecker* checker,
                                         SamplerSettings settings, unsigned seed)
    : ob::StateSampler(space), surfaces_(surfaces), validity_(validity), checker_(checker), settings_(settings) {
  rng_.setLocalSeed(seed);
  RBCP_CHECK(!surfaces_->empty(), "sampling needs at least one contact surface");
  double total = 0.0;
  for (const auto& s : *surfaces_) {
    std::vector<double> cdf;
    double area = 0.0;
    for (std::size_t k = 1; k + 1 < s.vertices.size(); ++k) {
      area += 0.5 * (s.vertices[k] - s.vertices[0]).cross(s.vertices[k + 1] - s.vertices[0]).norm();
      cdf.push_back(area);
    }
    triangle_area_cdf_.push_back(std::move(cdf));
    total += area;
    surface_area_cdf_.push_back(total);
  }
  v_max_ = static_cast<const RootStateSpace*>(space)->Limits().horizontal.v_max;
}

void SurfaceStateSampler::SampleOnce(ob::State* state) {
  const std::size_t n = surfaces_->size();
  std::size_t index = 0;
  if (rng_.uniform01() < settings_.area_weighted_probability && surface_area_cdf_.back() > 0.0) {
    const double u = rng_.uniformReal(0.0, surface_area_cdf_.back());
    index = static_cast<std::size_t>(std::upper_bound(surface_area_cdf_.begin(), surface_area_cdf_.end(), u) -
                                     surface_area_cdf_.begin());
    index = std::min(index, n - 1);
  } else {
    index = static_cast<std::size_t>(rng_.uniformInt(0, static_cast<int>(n) - 1));
  }
  const AffordanceSurface& surface = (*surfaces_)[index];
  const std::vector<double>& cdf = triangle_area_cdf_[index];
  std::size_t tri = 0;
  if (!cdf.empty() && cdf.back() > 0.0) {
    const double u = rng_.uniformReal(0.0, cdf.back());
    tri = std::min(cdf.size() - 1,
                   static_cast<std::size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()));
  }
  const Eigen::Vector3d& a = surface.vertices[0];
  const Eigen::Vector3d& b = surface.vertices[std::min(tri + 1, surface.vertices.size() - 1)];
  const Eigen::Vector3d& c = surface.vertices[std::min(tri + 2, surface.vertices.size() - 1)];
  double r1 = rng_.uniform01();
  double r2 = rng_.uniform01();
  if (r1 + r2 > 1.0) {
    r1 = 1.0 - r1;
    r2 = 1.0 - r2;
  }
  PointState point;
  point.p = a + r1 * (b - a) + r2 * (c - a);
  point.p.z() += settings_.standing_height + rng_.uniformReal(settings_.height_offset_min, settings_.height_offset_max);
  if (settings_.vertical_fixed) point.p.z() = settings_.fixed_height;
  if (rng_.uniform01() >= settings_.zero_velocity_probability) {
    const double heading = rng_.uniformReal(-M_PI, M_PI);
    const double speed = rng_.uniformReal(0.0, v_max_);
    // Per-axis bounds: a horizontal speed up to v_max in any direction stays within them.
    point.v = {speed * std::cos(heading), speed * std::sin(heading), 0.0};
  }
  RootStateSpace::Set(state, point, settings_.rest_yaw);
}

bool SurfaceStateSampler::Repair(ob::State* state) {
  PointState point = RootStateSpace::Point(state);
  const double rest_yaw = RootStateSpace::RestYaw(state);
  const double yaw = validity_->Yaw(point.v, rest_yaw);
  double below = -std::numeric_limits<double>::infinity();  // highest height found too low
  double above = std::numeric_limits<double>::infinity();   // lowest height found too high
  for (int move = 0; move <= settings_.repair_moves; ++move) {
    const ReachabilityReport report = checker_->Check(point.p, yaw);
    if (report.Valid()) {
      RootStateSpace::Set(state, point, rest_yaw);
      return true;
    }
    if (settings_.vertical_fixed || move == settings_.repair_moves) break;
    double& z = point.p.z();
    if (report.trunk_collision) {
      below = std::max(below, z);
      z = std::isfinite(above) ? 0.5 * (below + above) : z + settings_.repair_step;
    } else {
      above = std::min(above, z);
      z = std::isfinite(below) ? 0.5 * (below + above) : z - settings_.repair_step;
    }
  }
  return false;
}

void SurfaceStateSampler::sampleUniform(ob::State* state) {
  for (int attempt = 0; attempt < settings_.attempts; ++attempt) {
    SampleOnce(state);
    if (Repair(state)) return;
  }
}

void SurfaceStateSampler::sampleUniformNear(ob::State* state, const ob::State* /*near*/, double /*distance*/) {
  sampleUniform(state);
}

void SurfaceStateSampler::sampleGaussian(ob::State* state, const ob::State* /*mean*/, double /*std_dev*/) {
  sampleUniform(state);
}

// ---- Path -------------------------------------------------------------------------------------------

RootTrajectoryPath::RootTrajectoryPath(const ob::SpaceInformationPtr& si, RootPath path,
                                       const KinodynamicMotionValidator* validator)
    : ob::Path(si), path_(std::move(path)), validator_(validator) {}

ob::Cost RootTrajectoryPath::cost(const ob::OptimizationObjectivePtr& /*objective*/) const {
  return ob::Cost(path_.Duration());
}

bool RootTrajectoryPath::check() const {
  for (const auto& segment : path_.Segments()) {
    if (!validator_->IsValid(segment)) return false;
  }
  return true;
}

void RootTrajectoryPath::print(std::ostream& out) const {
  out << "root path: " << path_.Segments().size() << " pieces, " << path_.Duration() << " s\n";
  for (const auto& s : path_.SampleEvery(validator_->Settings().time_step)) {
    out << "  t " << s.t << " p " << s.p.transpose() << " v " << s.v.transpose() << " yaw " << s.yaw << "\n";
  }
}

// ---- Planner ------------------------------------------------------------------------------------------

KinodynamicBiRrt::KinodynamicBiRrt(const ob::SpaceInformationPtr& si, const KinodynamicMotionValidator* validator,
                                   SamplerSettings sampler_settings, const std::vector<AffordanceSurface>* surfaces,
                                   const ReachabilityValidityChecker* validity, ReachabilityChecker* checker,
                                   unsigned seed)
    : ob::Planner(si, "KinodynamicBiRRT"),
      validator_(validator),
      sampler_settings_(sampler_settings),
      surfaces_(surfaces),
      validity_(validity),
      checker_(checker),
      seed_(seed) {
  specs_.approximateSolutions = false;
  specs_.directed = true;
}

KinodynamicBiRrt::~KinodynamicBiRrt() { FreeTrees(); }

void KinodynamicBiRrt::FreeTrees() {
  for (Tree* tree : {&start_tree_, &goal_tree_}) {
    for (auto& node : *tree) {
      if (node.state != nullptr) si_->freeState(node.state);
    }
    tree->clear();
  }
}

void KinodynamicBiRrt::clear() {
  ob::Planner::clear();
  FreeTrees();
  stats_ = BiRrtStats{};
}

int KinodynamicBiRrt::AddNode(Tree& tree, const PointState& point, double rest_yaw, int parent,
                              const RootSegment& edge) {
  Node node;
  node.point = point;
  node.rest_yaw = rest_yaw;
  node.parent = parent;
  node.edge = edge;
  node.state = si_->allocState();
  RootStateSpace::Set(node.state, point, rest_yaw);
  tree.push_back(std::move(node));
  return static_cast<int>(tree.size()) - 1;
}

int KinodynamicBiRrt::Nearest(const Tree& tree, const PointState& target, bool towards_target) const {
  const KinodynamicLimits& limits = validator_->Settings().limits;
  int best = 0;
  double best_time = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d inverse_speed(1.0 / limits.horizontal.v_max, 1.0 / limits.horizontal.v_max,
                                      limits.VerticalFixed() ? 0.0 : 1.0 / limits.vertical.v_max);
  for (std::size_t i = 0; i < tree.size(); ++i) {
    // |v| <= v_max bounds the time from below by the displacement over v_max; skip states that
    // cannot beat the best one.
    const double bound = ((tree[i].point.p - target.p).cwiseAbs().cwiseProduct(inverse_speed)).maxCoeff();
    if (bound >= best_time) continue;
    const double t = towards_target ? MinimumTimeBound(tree[i].point, target, limits)
                                    : MinimumTimeBound(target, tree[i].point, limits);
    if (t < best_time) {
      best_time = t;
      best = static_cast<int>(i);
    }
  }
  return best;
}

bool KinodynamicBiRrt::Compatible(const PointState& point, double rest_a, double rest_b) const {
  return std::abs(WrapAngle(rest_a - rest_b)) < 1e-9 ||
         point.v.head<2>().norm() >= validator_->Settings().yaw.blend_speed;
}

RootPath KinodynamicBiRrt::Chain(int start_node, const std::optional<RootSegment>& bridge, int goal_node) const {
  RootPath path(validator_->Settings().yaw);
  std::vector<const RootSegment*> outbound;
  for (int i = start_node; i > 0; i = start_tree_[static_cast<std::size_t>(i)].parent) {
    outbound.push_back(&start_tree_[static_cast<std::size_t>(i)].edge);
  }
  for (auto it = outbound.rbegin(); it != outbound.rend(); ++it) {
    if ((*it)->Duration() > 0.0) path.Append(**it);
  }
  if (bridge && bridge->Duration() > 0.0) path.Append(*bridge);
  for (int i = goal_node; i > 0; i = goal_tree_[static_cast<std::size_t>(i)].parent) {
    const RootSegment& edge = goal_tree_[static_cast<std::size_t>(i)].edge;
    if (edge.Duration() > 0.0) path.Append(edge);
  }
  return path;
}

ob::PlannerStatus KinodynamicBiRrt::AddSolution(RootPath path) {
  stats_.start_tree_states = static_cast<int>(start_tree_.size());
  stats_.goal_tree_states = static_cast<int>(goal_tree_.size());
  pdef_->addSolutionPath(std::make_shared<RootTrajectoryPath>(si_, std::move(path), validator_), false, 0.0, getName());
  return ob::PlannerStatus(ob::PlannerStatus::EXACT_SOLUTION);
}

std::optional<RootPath> KinodynamicBiRrt::ConnectDirectly(double rest_start, double rest_goal) {
  auto direct = validator_->Steer(start_tree_[0].point, rest_start, goal_tree_[0].point, rest_goal);
  if (!direct) return std::nullopt;
  const double prefix = validator_->ValidPrefix(*direct);
  if (prefix >= direct->Duration() - kTimeTolerance) return Chain(0, direct, 0);
  if (prefix > 0.0) {
    const RootPathSample s = direct->Sample(prefix, validator_->Settings().yaw);
    // Along the start tree the rest yaw stays the start's: re-steer the prefix part with it.
    RootSegment part = direct->Part(0.0, prefix);
    part.rest_yaw_begin = part.rest_yaw_end = rest_start;
    if (std::abs(WrapAngle(rest_goal - rest_start)) < 1e-9) {
      AddNode(start_tree_, PointState{s.p, s.v}, rest_start, 0, part);
    }
  }
  return std::nullopt;
}

KinodynamicBiRrt::Extension KinodynamicBiRrt::ExtendStartTree(const PointState& target, double rest_start) {
  Extension extension;
  const int near = Nearest(start_tree_, target, true);
  auto piece = validator_->Steer(start_tree_[static_cast<std::size_t>(near)].point, rest_start, target, rest_start);
  if (!piece) return extension;
  const double prefix = validator_->ValidPrefix(*piece);
  if (prefix > 0.0) {
    const RootPathSample s = piece->Sample(prefix, validator_->Settings().yaw);
    extension.node = AddNode(start_tree_, PointState{s.p, s.v}, rest_start, near, piece->Part(0.0, prefix));
    extension.reached = prefix >= piece->Duration() - kTimeTolerance;
  }
  return extension;
}

KinodynamicBiRrt::Extension KinodynamicBiRrt::ExtendGoalTree(const PointState& target, double rest_goal) {
  Extension extension;
  const int near = Nearest(goal_tree_, target, false);
  auto piece = validator_->Steer(target, rest_goal, goal_tree_[static_cast<std::size_t>(near)].point, rest_goal);
  if (!piece) return extension;
  const double suffix = validator_->ValidSuffix(*piece);
  if (suffix < piece->Duration() - kTimeTolerance) {
    const RootPathSample s = piece->Sample(suffix, validator_->Settings().yaw);
    extension.node = AddNode(goal_tree_, PointState{s.p, s.v}, rest_goal, near, piece->Part(suffix, piece->Duration()));
    extension.reached = suffix <= kTimeTolerance;
  }
  return extension;
}

std::optional<RootPath> KinodynamicBiRrt::Join(const Extension& from_start, const Extension& from_goal,
                                               double rest_start, double rest_goal) const {
  std::optional<RootPath> joined;
  auto try_join = [&](int s, int g) {
    const Node& a = start_tree_[static_cast<std::size_t>(s)];
    const Node& b = goal_tree_[static_cast<std::size_t>(g)];
    auto bridge = validator_->Steer(a.point, rest_start, b.point, rest_goal);
    if (bridge && bridge->Duration() > 0.0 && validator_->IsValid(*bridge)) joined = Chain(s, bridge, g);
  };
  if (from_start.node >= 0) {
    try_join(from_start.node, Nearest(goal_tree_, start_tree_[static_cast<std::size_t>(from_start.node)].point, false));
  }
  if (!joined && from_goal.node >= 0) {
    const int s = Nearest(start_tree_, goal_tree_[static_cast<std::size_t>(from_goal.node)].point, true);
    // The pair (new start, new goal) when both reached the sample is the same state: the
    // previous join attempt already covered its neighbourhood.
    if (!(s == from_start.node && from_start.reached && from_goal.reached)) try_join(s, from_goal.node);
  }
  return joined;
}

ob::PlannerStatus KinodynamicBiRrt::solve(const ob::PlannerTerminationCondition& ptc) {
  checkValidity();
  clear();
  const ob::State* start_state = pis_.nextStart();
  if (start_state == nullptr) return ob::PlannerStatus::INVALID_START;
  const auto* goal = pdef_->getGoal()->as<ob::GoalState>();
  const ob::State* goal_state = goal->getState();
  const double rest_start = RootStateSpace::RestYaw(start_state);
  const double rest_goal = RootStateSpace::RestYaw(goal_state);
  AddNode(start_tree_, RootStateSpace::Point(start_state), rest_start, -1, RootSegment{});
  AddNode(goal_tree_, RootStateSpace::Point(goal_state), rest_goal, -1, RootSegment{});
  if (std::optional<RootPath> direct = ConnectDirectly(rest_start, rest_goal)) return AddSolution(std::move(*direct));

  SurfaceStateSampler sampler(si_->getStateSpace().get(), surfaces_, validity_, checker_, sampler_settings_, seed_);
  ob::State* target_state = si_->allocState();
  ob::PlannerStatus status = ob::PlannerStatus::TIMEOUT;
  while (stats_.iterations < max_iterations_ && !ptc()) {
    ++stats_.iterations;
    sampler.sampleUniform(target_state);
    const PointState target = RootStateSpace::Point(target_state);
    const Extension from_start = ExtendStartTree(target, rest_start);
    const Extension from_goal = ExtendGoalTree(target, rest_goal);
    // Both trees reached the sample: it joins them when its rest yaws agree there.
    if (from_start.node >= 0 && from_goal.node >= 0 && from_start.reached && from_goal.reached &&
        Compatible(target, rest_start, rest_goal)) {
      status = AddSolution(Chain(from_start.node, std::nullopt, from_goal.node));
      break;
    }
    if (std::optional<RootPath> joined = Join(from_start, from_goal, rest_start, rest_goal)) {
      status = AddSolution(std::move(*joined));
      break;
    }
  }
  si_->freeState(target_state);
  stats_.start_tree_states = static_cast<int>(start_tree_.size());
  stats_.goal_tree_states = static_cast<int>(goal_tree_.size());
  return status;
}

void KinodynamicBiRrt::getPlannerData(ob::PlannerData& data) const {
  ob::Planner::getPlannerData(data);
  for (const auto& node : start_tree_) {
    if (node.parent < 0) {
      data.addStartVertex(ob::PlannerDataVertex(node.state, 1));
    } else {
      data.addEdge(ob::PlannerDataVertex(start_tree_[static_cast<std::size_t>(node.parent)].state, 1),
                   ob::PlannerDataVertex(node.state, 1));
    }
  }
  for (const auto& node : goal_tree_) {
    if (node.parent < 0) {
      data.addGoalVertex(ob::PlannerDataVertex(node.state, 2));
    } else {
      data.addEdge(ob::PlannerDataVertex(node.state, 2),
                   ob::PlannerDataVertex(goal_tree_[static_cast<std::size_t>(node.parent)].state, 2));
    }
  }
}

}  // namespace rbcp::detail
