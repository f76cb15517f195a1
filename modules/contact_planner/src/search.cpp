#include "search.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "crawl_order.h"
#include "feet_kept.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/robot/robot_model.h"
#include "step.h"

namespace rbcp::contact_planner_detail {
namespace {

/// Two footholds of one leg closer than this are the same step when searching [m].
constexpr double kSameFoothold = 0.01;

long TimeKey(double t) { return std::lround(t * 1e6); }

/// What decides a node's subtree: its path time, body shift, footholds, the leg that moved last
/// and the crawl's count of steps without the trunk advancing; lengths to the micrometre. The
/// search from a node depends on nothing else, so a node that was a dead end (its step undone
/// after every step from it failed) is one wherever the search meets it again.
using StateKey = std::array<long long, 3 + 3 + 3 * kNumLegs>;
StateKey KeyOf(const Node& n) {
  StateKey key{};
  std::size_t i = 0;
  const auto length = [](double m) { return std::llround(m * 1e6); };
  long long stepped = 0;
  for (int leg = 0; leg < kNumLegs; ++leg) stepped |= (n.stepped_at_time[static_cast<std::size_t>(leg)] ? 1LL : 0LL) << leg;
  key[i++] = TimeKey(n.t);
  key[i++] = n.steps_at_time * 16 + stepped;
  key[i++] = n.state.moving_leg;
  for (int k = 0; k < 3; ++k) key[i++] = length(n.shift[k]);
  for (const FootContact& foot : n.state.feet) {
    for (int k = 0; k < 3; ++k) key[i++] = length(foot.position[k]);
  }
  return key;
}

/// Whether `leg` may step from `node` at path time t: always once the trunk has advanced;
/// without it, at most retry.max_steps_at_one_time steps and each leg once.
bool MayStep(const ContactPlannerConfig& config, const Node& node, Leg leg, double t) {
  const bool same_time = t <= node.t + 1e-9;
  if (!same_time) return true;
  if (node.steps_at_time >= config.retry.max_steps_at_one_time) return false;
  return !node.stepped_at_time[static_cast<std::size_t>(Index(leg))];
}

/// The legs with the horizontal distance of their foot from its reference position at the path
/// end, farthest first (ties in kTieOrder).
std::vector<std::pair<double, Leg>> LegsByGoalDistance(const PlannerContext& ctx, const PathTrack& path,
                                                       const Node& node) {
  const Eigen::Isometry3d end = PathBasePose(path.At(path.End()));
  std::vector<std::pair<double, Leg>> far;
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d goal = end * ctx.robot.ReferenceFootPosition(leg);
    far.push_back({(node.state.feet[static_cast<std::size_t>(Index(leg))].position - goal).head<2>().norm(), leg});
  }
  std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) {
    if (a.first != b.first) return a.first > b.first;
    return TieRank(a.second) < TieRank(b.second);
  });
  return far;
}

/// Fills the node's options (or marks it the goal) and marks it expanded. At the path end the
/// feet far from their goal positions are re-placed; elsewhere the keep phase decides when and
/// which legs step. Returns the keep phase's failure, when a leg must step.
std::optional<Failure> Expand(const PlannerContext& ctx, const PathTrack& path, double gait_advance, Node& node) {
  const ContactPlannerConfig& config = ctx.config;
  RBCP_CHECK(node.state.moving_leg >= -1 && node.state.moving_leg < kNumLegs,
             "moving leg " + std::to_string(node.state.moving_leg));
  node.expanded = true;
  const double end = path.End();
  const int n_leads = static_cast<int>(config.foothold.lead_time_factors.size());
  const auto allowed = [&](Leg leg, double t) { return MayStep(config, node, leg, t); };
  if (node.t >= end - 1e-9) {
    // At the path end: re-place the feet far from their goal positions.
    const std::vector<std::pair<double, Leg>> far = LegsByGoalDistance(ctx, path, node);
    if (far.front().first <= config.goal_foot_tolerance_m) {
      node.goal = true;
      return std::nullopt;
    }
    for (const auto& [d, leg] : far) {
      if (allowed(leg, end)) node.options.push_back({leg, end, 0, true, 0});
    }
    return std::nullopt;
  }
  const KeptFeetAdvance keep = AdvanceWithFeetKept(ctx, path, node);
  RBCP_CHECK(keep.ranking.size() == static_cast<std::size_t>(kNumLegs), "the keep phase ranks every leg");
  if (keep.reached_end) {
    // The trunk reaches the path end with these feet: the remaining steps happen there.
    for (const auto& [d, leg] : LegsByGoalDistance(ctx, path, node)) node.options.push_back({leg, end, 0, true, 0});
    return std::nullopt;
  }
  std::vector<double> times = {keep.t_last_keepable};
  for (double back : config.retry.earlier_step_s) {
    const double t = std::max(node.t, keep.t_last_keepable - back);
    if (std::none_of(times.begin(), times.end(), [&](double x) { return std::abs(x - t) < 1e-9; })) times.push_back(t);
  }
  // Crawl prior: after a hind leg, the fore leg on the same side steps next if it must.
  std::vector<LegRank> ranking = keep.ranking;
  if (node.state.moving_leg == Index(Leg::kLH) || node.state.moving_leg == Index(Leg::kRH)) {
    const Leg fore = node.state.moving_leg == Index(Leg::kLH) ? Leg::kLF : Leg::kRF;
    std::stable_partition(ranking.begin(), ranking.end(),
                          [&](const LegRank& r) { return r.failing && r.leg == fore; });
  }
  // Crawl timing: the next leg in the crawl order steps after gait_advance_s of path time, from
  // the parent's shift first, then from the path pose, with other leads and shift starts. When a
  // foot can no longer be kept before then, the failing legs step first: the crawl's leg would
  // step at the failure time, and the failing leg right after it at the same time.
  // A leg at time t with every target lead, then from every other start of the shift search.
  const auto add_every_lead_and_shift_start = [&](Leg leg, double t) {
    for (int lead = 0; lead < n_leads; ++lead) node.options.push_back({leg, t, lead, false, 0});
    for (int start = 1; start < NumShiftStarts(config); ++start) {
      if ((ShiftStart(config, node, start) - ShiftStart(config, node, 0)).norm() < 1e-9) continue;  // same start
      node.options.push_back({leg, t, 0, false, start});
    }
  };
  if (gait_advance > 0.0) {
    const double t_gait = std::min(keep.t_last_keepable, node.t + gait_advance);
    const Leg gait_leg = node.state.moving_leg < 0 ? ranking.front().leg
                                                   : CrawlNext(kAllLegs[static_cast<std::size_t>(node.state.moving_leg)]);
    const bool before_failure = node.t + gait_advance < keep.t_last_keepable - 1e-9;
    const bool gait_leg_fails = std::any_of(ranking.begin(), ranking.end(),
                                            [&](const LegRank& r) { return r.failing && r.leg == gait_leg; });
    if ((before_failure || gait_leg_fails) && allowed(gait_leg, t_gait)) {
      add_every_lead_and_shift_start(gait_leg, t_gait);
    }
  }
  // Failing legs at the failure time, every lead, then with the other starts of the shift
  // search; then earlier; then the other legs.
  for (const LegRank& r : ranking) {
    if (r.failing && allowed(r.leg, keep.t_last_keepable)) add_every_lead_and_shift_start(r.leg, keep.t_last_keepable);
  }
  for (std::size_t k = 1; k < times.size(); ++k) {
    for (const LegRank& r : ranking) {
      if (r.failing && allowed(r.leg, times[k])) node.options.push_back({r.leg, times[k], 0, false, 0});
    }
  }
  for (double t : times) {
    for (const LegRank& r : ranking) {
      if (!r.failing && allowed(r.leg, t)) node.options.push_back({r.leg, t, 0, false, 0});
    }
  }
  if (keep.ranking.front().failing) {
    RBCP_CHECK(keep.stop.has_value(), "a keep phase short of the path end says what stopped it");
    return Failure{keep.t_last_keepable, Index(keep.ranking.front().leg), *keep.stop};
  }
  return std::nullopt;
}

}  // namespace

std::string Failure::Describe() const {
  RBCP_CHECK(leg >= -1 && leg < kNumLegs, "failure leg " + std::to_string(leg));
  const auto what_text = [this]() -> std::string {
    if (const auto* stop = std::get_if<KeepStop>(&what)) return stop->Describe();
    if (const auto* step = std::get_if<StepFailure>(&what)) return step->Describe();
    return "";
  };
  if (leg < 0) return "no valid step: " + what_text();
  std::string r = std::string("no valid step for ") + std::string(LegName(kAllLegs[static_cast<std::size_t>(leg)])) +
                  " at path time " + FixedNumber(t, 2) + " s";
  if (!std::holds_alternative<std::monostate>(what)) r += ": " + what_text();
  return r;
}

namespace {

/// The node's state and its place in the crawl, without the search's bookkeeping.
Node Unexpanded(const Node& n) {
  Node fresh;
  fresh.state = n.state;
  fresh.t = n.t;
  fresh.shift = n.shift;
  fresh.steps_at_time = n.steps_at_time;
  fresh.stepped_at_time = n.stepped_at_time;
  return fresh;
}

bool EvaluationsSpent(const PlannerContext& ctx) { return ctx.stats.Evaluations() >= ctx.config.retry.max_evaluations; }

std::string EvaluationsReason(const PlannerContext& ctx) {
  return "search bound of " + std::to_string(ctx.config.retry.max_evaluations) + " leg evaluations spent";
}

/// The depth-first search of Search(): the stack of nodes from the root, the states found to be
/// dead ends, and the failure furthest along the path.
class DepthFirstSearch {
 public:
  DepthFirstSearch(const PlannerContext& ctx, const PathTrack& path, const CrawlProfile& profile, int max_steps,
                   std::vector<Node>* path_to_furthest)
      : ctx_(ctx),
        path_(path),
        profile_(profile),
        max_steps_(max_steps),
        path_to_furthest_(path_to_furthest),
        first_evaluation_(ctx.stats.Evaluations()) {}

  ContactPlanResult Run(Node root) {
    stack_.push_back(std::move(root));
    if (path_to_furthest_) *path_to_furthest_ = {Unexpanded(stack_.front())};
    while (true) {
      if (std::optional<ContactPlanResult> stopped = LimitReached()) return *stopped;
      RBCP_CHECK(!stack_.empty(), "the root is never undone");
      Node& node = stack_.back();
      if (!node.expanded) ExpandTop();
      if (node.goal) break;
      if (node.next_option < node.options.size() &&
          static_cast<int>(node.children.size()) < ctx_.config.retry.max_children_per_state) {
        TryNextOption();
        continue;
      }
      // Every option failed: undo this node's step.
      if (stack_.size() == 1 || backtracks_ >= ctx_.config.retry.max_backtracks) {
        return Failed(ContactPlanStatus::kNoFoothold,
                      furthest_failure_.Describe() + (stack_.size() == 1 ? "" : " (backtracking limit reached)"));
      }
      dead_ends_.insert(KeyOf(stack_.back()));
      stack_.pop_back();
      ++backtracks_;
      ++ctx_.stats.backtracks;
    }
    result_.ok = true;
    result_.status = ContactPlanStatus::kOk;
    for (const Node& n : stack_) result_.plan.states.push_back(n.state);
    result_.steps = static_cast<int>(result_.plan.states.size()) - 1;
    return result_;
  }

 private:
  ContactPlanResult Failed(ContactPlanStatus status, const std::string& reason) {
    result_.ok = false;
    result_.status = status;
    result_.reason = reason;
    result_.failure_time_s = furthest_failure_.t;
    result_.failure_leg = furthest_failure_.leg;
    return result_;
  }

  /// The search's answer when the time budget, the query's evaluation bound or this search's
  /// share of it is spent; nullopt to go on.
  std::optional<ContactPlanResult> LimitReached() {
    const ContactPlannerConfig& config = ctx_.config;
    if (ctx_.budget.Exhausted()) {
      return Failed(ContactPlanStatus::kTimeout, "time budget of " + FixedNumber(config.time_budget_s, 2) +
                                                     " s exhausted; furthest failure: " + furthest_failure_.Describe());
    }
    if (EvaluationsSpent(ctx_)) {
      return Failed(ContactPlanStatus::kNoFoothold,
                    EvaluationsReason(ctx_) + "; furthest failure: " + furthest_failure_.Describe());
    }
    if (ctx_.stats.Evaluations() - first_evaluation_ >= config.retry.max_search_evaluations) {
      return Failed(ContactPlanStatus::kNoFoothold,
                    furthest_failure_.Describe() + " (" + std::to_string(config.retry.max_search_evaluations) +
                        " leg evaluations spent in this search)");
    }
    return std::nullopt;
  }

  /// Gives the top node its options, or marks it the goal (also once max_steps steps are made).
  void ExpandTop() {
    Node& node = stack_.back();
    const int steps = static_cast<int>(stack_.size()) - 1;
    if (max_steps_ >= 0 && steps >= max_steps_) {
      node.expanded = true;
      node.goal = true;
      result_.reached_goal = false;
      return;
    }
    if (std::optional<Failure> keep_failure = Expand(ctx_, path_, profile_.gait_advance_s, node)) {
      furthest_failure_.Note(std::move(*keep_failure));
    }
    if (node.goal) result_.reached_goal = true;
  }

  /// Tries the top node's next option: a step found goes on the stack; a stance leg that blocks
  /// it is re-placed first.
  void TryNextOption() {
    Node& node = stack_.back();
    const Node::Option option = node.options[node.next_option++];
    const std::tuple<int, long, int> key{Index(option.leg), TimeKey(option.t), option.shift_start};
    if (node.exhausted.count(key)) return;
    StepAttempt attempt = TryStep(ctx_, path_, node, option, profile_);
    if (attempt.blocking) RePlaceFirst(node, option, *attempt.blocking);
    const StepOutcome outcome = attempt.outcome();
    if (outcome == StepOutcome::kFound) return Push(node, option, std::move(attempt.child));
    if (outcome == StepOutcome::kNoCandidate || outcome == StepOutcome::kPoseInvalid) node.exhausted.insert(key);
    furthest_failure_.Note({option.t, Index(option.leg), std::move(*attempt.failure)});
  }

  /// A stance leg hits the terrain (a riser, a wall) when the body shifts for this swing, or
  /// narrows the swing's support triangle: re-place that leg first, at the same time, before the
  /// remaining options.
  void RePlaceFirst(Node& node, const Node::Option& option, Leg blocker) const {
    RBCP_CHECK(blocker != option.leg, "a leg does not block its own lift-off");
    if (MayStep(ctx_.config, node, blocker, option.t) &&
        node.repositions.insert({Index(blocker), TimeKey(option.t)}).second) {
      node.options.insert(node.options.begin() + static_cast<std::ptrdiff_t>(node.next_option),
                          Node::Option{blocker, option.t, 0, option.goal_step, 0});
    }
  }

  /// Puts the child found by `option` on the stack, unless the same step was explored from
  /// `node` already or its state is a dead end.
  void Push(Node& node, const Node::Option& option, Node child) {
    const Eigen::Vector3d& foot = child.state.feet[static_cast<std::size_t>(Index(option.leg))].position;
    const bool duplicate = std::any_of(node.children.begin(), node.children.end(), [&](const auto& c) {
      return c.leg == option.leg && std::abs(c.t - child.t) < 1e-9 && (c.foot - foot).norm() < kSameFoothold;
    });
    // Reached by another way (failed already), or a step whose dynamic walk failed.
    if (duplicate || dead_ends_.count(KeyOf(child)) || IsAvoided(ctx_.avoided, node.state, child.state)) return;
    node.children.push_back({option.leg, child.t, foot});
    stack_.push_back(std::move(child));
    if (path_to_furthest_ && stack_.back().t > path_to_furthest_->back().t + 1e-9) {
      path_to_furthest_->clear();
      for (const Node& n : stack_) path_to_furthest_->push_back(Unexpanded(n));
    }
  }

  const PlannerContext& ctx_;
  const PathTrack& path_;
  const CrawlProfile& profile_;
  const int max_steps_;
  std::vector<Node>* const path_to_furthest_;
  const long long first_evaluation_;
  ContactPlanResult result_;
  std::vector<Node> stack_;
  std::set<StateKey> dead_ends_;
  Failure furthest_failure_;
  int backtracks_ = 0;
};

}  // namespace

ContactPlanResult Search(const PlannerContext& ctx, const PathTrack& path, const CrawlProfile& profile, Node root,
                         int max_steps, std::vector<Node>* path_to_furthest) {
  return DepthFirstSearch(ctx, path, profile, max_steps, path_to_furthest).Run(std::move(root));
}

namespace {

/// One search of SearchWithRetries' sequence: a crawl profile from the root or from the restart
/// state of the first search.
struct RetryTask {
  RetryTask(std::size_t profile_index, bool root) : profile(profile_index), from_root(root) {}

  std::size_t profile = 0;  ///< index into the profiles
  bool from_root = true;
  // Set when it has run (by whichever thread): its answer and the work it did.
  bool started = false;
  bool done = false;
  ContactPlanResult result;
  ContactPlanStats work;
};

std::string Describe(const CrawlProfile& p) {
  return "gait_advance_s " + FixedNumber(p.gait_advance_s, 2) + " s, keep_fraction " + FixedNumber(p.keep_fraction, 2);
}

/// The searches of a query, in the order their answers count, run one after another or by
/// several threads at once. The answer is the first search's that finds a plan (or stops for
/// another reason than a want of footholds) in that order, with the work counted up to it: the
/// same plan and stats whatever the number of threads.
class RetrySequence {
 public:
  RetrySequence(const PlannerContext& ctx, const PathTrack& path, const Node& root, int max_steps)
      : ctx_(ctx), path_(path), root_(root), max_steps_(max_steps), base_stats_(ctx.stats) {
    const ContactPlannerConfig& config = ctx.config;
    std::vector<double> timings = {config.gait_advance_s};
    timings.insert(timings.end(), config.retry.gait_advance_s.begin(), config.retry.gait_advance_s.end());
    std::vector<double> fractions = {config.base_shift.keep_fraction};
    fractions.insert(fractions.end(), config.retry.keep_fraction.begin(), config.retry.keep_fraction.end());
    for (const double advance : timings) {
      for (const double fraction : fractions) profiles_.push_back({advance, fraction});
    }
    // The first search; the other profiles from the restart state (if the first search leaves
    // one); then from the root.
    tasks_.emplace_back(0, true);
    for (const bool from_root : {false, true}) {
      for (std::size_t k = 1; k < profiles_.size(); ++k) tasks_.emplace_back(k, from_root);
    }
  }

  ContactPlanResult Run(const std::vector<StaticEquilibrium*>& spare) {
    if (spare.empty()) return InOrderFrom(0);
    // One thread per LP workspace searches the tasks in order; this one takes their answers as
    // they come (a search whose answer is not needed any more is cancelled).
    std::vector<std::thread> helpers;
    helpers.emplace_back([this] { Help(ctx_.equilibrium); });
    for (StaticEquilibrium* eq : spare) helpers.emplace_back([this, eq] { Help(*eq); });
    std::unique_lock<std::mutex> lock(mutex_);
    std::size_t i = 0;  // the next task in order whose answer is not yet taken
    long offset = 0;    // leg evaluations of the tasks before i
    std::optional<ContactPlanResult> answer;
    while (!error_) {
      if (i == tasks_.size()) {
        answer = Exhausted(i);
        break;
      }
      if (Skipped(i)) {
        ++i;
        continue;
      }
      if (!WithinBound(i, offset)) {
        answer = Exhausted(i);
        break;
      }
      if (!tasks_[i].done) {
        finished_.wait(lock);
        continue;
      }
      // Task i ran with the query's evaluation bound counted from the base; in order it starts
      // `offset` later. Where the bound may have cut it, its answer depends on that: from here,
      // the tasks run in order.
      if (offset > 0 && base_stats_.Evaluations() + offset + tasks_[i].work.Evaluations() >= ctx_.config.retry.max_evaluations) {
        break;
      }
      offset += tasks_[i].work.Evaluations();
      if ((answer = Answer(i))) break;
      ++i;
    }
    stop_ = true;
    lock.unlock();
    finished_.notify_all();
    for (std::thread& t : helpers) t.join();
    stop_ = false;
    if (error_) std::rethrow_exception(error_);
    if (answer) return *answer;
    for (std::size_t k = i; k < tasks_.size(); ++k) tasks_[k] = RetryTask(tasks_[k].profile, tasks_[k].from_root);
    return InOrderFrom(i);
  }

 private:
  /// The tasks one after another from `from` (the ones before it have run and failed), in the
  /// query's context.
  ContactPlanResult InOrderFrom(std::size_t from) {
    long offset = 0;
    for (std::size_t i = 0; i < from; ++i) offset += tasks_[i].work.Evaluations();
    for (std::size_t i = from; i < tasks_.size(); ++i) {
      if (Skipped(i)) continue;
      if (!WithinBound(i, offset)) return Exhausted(i);
      RunTask(i, ctx_.equilibrium, true);
      offset += tasks_[i].work.Evaluations();
      if (std::optional<ContactPlanResult> answer = Answer(i)) return *answer;
    }
    return Exhausted(tasks_.size());
  }

  /// A search thread: searches the next task not yet started until there is none or the answer is known.
  void Help(StaticEquilibrium& equilibrium) {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      if (std::optional<std::size_t> next = NextTask()) {
        lock.unlock();
        RunTask(*next, equilibrium, false);
        lock.lock();
      } else {
        finished_.wait(lock);
      }
    }
  }

  /// The first task in order not yet started that can start (a restart task once the first
  /// search has told the restart state). Call with the mutex held; marks it started.
  std::optional<std::size_t> NextTask() {
    if (stop_) return std::nullopt;
    for (std::size_t i = 0; i < tasks_.size(); ++i) {
      if (tasks_[i].started) continue;
      if (!tasks_[i].from_root && !tasks_[0].done) continue;  // needs the restart state
      if (Skipped(i)) continue;
      tasks_[i].started = true;
      return i;
    }
    return std::nullopt;
  }

  /// True for a restart task when the first search left no restart state (it has run).
  bool Skipped(std::size_t i) const { return !tasks_[i].from_root && tasks_[0].done && restart_ == 0; }

  /// Whether the query's evaluation bound lets task i start, `offset` evaluations after the base.
  bool WithinBound(std::size_t i, long offset) const {
    return i == 0 || base_stats_.Evaluations() + offset < ctx_.config.retry.max_evaluations;
  }

  /// Runs task i with its own counters, budget and LP workspace. In order, its counters start
  /// with the work of the tasks before it (the query's evaluation bound counts it); otherwise
  /// from the base, and Run() checks that the bound did not bind.
  void RunTask(std::size_t i, StaticEquilibrium& equilibrium, bool in_order) {
    RetryTask& task = tasks_[i];
    ContactPlanStats before = base_stats_;
    if (in_order) {
      for (std::size_t k = 0; k < i; ++k) before += tasks_[k].work;
    }
    ContactPlanStats stats = before;
    TimeBudget budget = ctx_.budget.CancelledBy(&stop_);
    BodyPoseData body_poses;
    const PlannerContext ctx{ctx_.robot,   ctx_.db,       ctx_.eq_config, ctx_.config, ctx_.stance,
                             ctx_.surfaces, ctx_.avoided, equilibrium, stats, budget, body_poses};
    const Node& start = task.from_root ? root_ : restart_node_;
    const int steps = max_steps_ < 0 || task.from_root ? max_steps_ : max_steps_ - static_cast<int>(restart_);
    std::vector<Node> path_to_furthest;
    ContactPlanResult result;
    try {
      result = Search(ctx, path_, profiles_[task.profile], start, steps,
                      i == 0 && ctx_.config.retry.restart_back_s > 0.0 ? &path_to_furthest : nullptr);
    } catch (...) {
      if (in_order) throw;
      // On another thread: handed to Run(), which stops the others and throws it.
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      stop_ = true;
      finished_.notify_all();
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    task.result = std::move(result);
    task.work = stats - before;
    task.done = true;
    if (i == 0) SetRestart(path_to_furthest);
    finished_.notify_all();
  }

  /// The restart state from the states of the first search's path to its furthest node.
  void SetRestart(const std::vector<Node>& path_to_furthest) {
    restart_ = 0;
    if (path_to_furthest.empty()) return;
    const double t_restart = path_to_furthest.back().t - ctx_.config.retry.restart_back_s;
    for (std::size_t k = 0; k < path_to_furthest.size() && path_to_furthest[k].t <= t_restart + 1e-9; ++k) restart_ = k;
    // A piece of a receding horizon counts its steps from the root: the restarted search makes
    // the ones left, and none when the restart state already has them all.
    if (max_steps_ >= 0 && static_cast<int>(restart_) >= max_steps_) restart_ = 0;
    restart_prefix_.clear();
    for (std::size_t k = 0; k < restart_; ++k) restart_prefix_.push_back(path_to_furthest[k].state);
    if (restart_ > 0) restart_node_ = path_to_furthest[restart_];
  }

  /// Task i's answer when it ends the sequence (a plan, or a stop for another reason than a
  /// want of footholds), with the work of the tasks up to it; nullopt to go on.
  std::optional<ContactPlanResult> Answer(std::size_t i) {
    RetryTask& task = tasks_[i];
    if (!task.result.ok && task.result.status == ContactPlanStatus::kNoFoothold) {
      if (i > 0) tried_ += (tried_.empty() ? "" : "; ") + Describe(profiles_[task.profile]) + Where(task);
      return std::nullopt;
    }
    ContactPlanResult answer = task.result;
    if (i > 0 && answer.status == ContactPlanStatus::kTimeout) {
      // The wall clock is a safety limit: the answer is the first search's failure, naming the
      // retry the clock ended.
      answer = tasks_[0].result;
      answer.status = ContactPlanStatus::kTimeout;
      answer.reason = "time budget of " + FixedNumber(ctx_.config.time_budget_s, 2) + " s exhausted in the retry with " +
                      Describe(profiles_[task.profile]) + Where(task) + "; first search: " + tasks_[0].result.reason;
    }
    if (answer.ok && !task.from_root) {
      // The steps of the first search up to the restart state, then the new ones.
      std::vector<WholeBodyState> states = restart_prefix_;
      states.insert(states.end(), answer.plan.states.begin(), answer.plan.states.end());
      answer.plan.states = std::move(states);
      answer.steps = static_cast<int>(answer.plan.states.size()) - 1;
    }
    CountWorkUpTo(i);
    return answer;
  }

  /// The first search's failure once the sequence ends before task i (every task before it
  /// failed for want of footholds, and task i may not start), with the work of those tasks.
  ContactPlanResult Exhausted(std::size_t i) {
    ContactPlanResult first = tasks_[0].result;
    if (!tried_.empty()) first.reason += " (also with " + tried_ + ")";
    CountWorkUpTo(i == 0 ? 0 : i - 1);
    return first;
  }

  void CountWorkUpTo(std::size_t last) {
    for (std::size_t k = 0; k <= last && k < tasks_.size(); ++k) {
      if (tasks_[k].done) ctx_.stats += tasks_[k].work;
    }
  }

  std::string Where(const RetryTask& task) const {
    return task.from_root ? "" : " from path time " + FixedNumber(restart_node_.t, 2) + " s";
  }

  const PlannerContext& ctx_;
  const PathTrack& path_;
  const Node& root_;
  const int max_steps_;
  const ContactPlanStats base_stats_;
  std::vector<CrawlProfile> profiles_;
  std::vector<RetryTask> tasks_;
  std::size_t restart_ = 0;
  Node restart_node_;
  std::vector<WholeBodyState> restart_prefix_;
  std::string tried_;
  std::mutex mutex_;
  std::condition_variable finished_;
  std::atomic<bool> stop_{false};
  std::exception_ptr error_;  ///< the first exception of a search run by Run()
};

}  // namespace

ContactPlanResult SearchWithRetries(const PlannerContext& ctx, const PathTrack& path, const Node& root, int max_steps,
                                    const std::vector<StaticEquilibrium*>& spare) {
  RetrySequence sequence(ctx, path, root, max_steps);
  return sequence.Run(spare);
}

}  // namespace rbcp::contact_planner_detail
