#pragma once
/// The step search: depth first from a root node, each node's options from its keep phase
/// (which leg steps, when, toward which target and from which start of the shift search),
/// backtracking when every option of a node fails, and the whole search again with other crawl
/// timings when it runs out of options.

#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "feet_kept.h"
#include "path_track.h"
#include "planner_context.h"
#include "rbcp/contact_planner/contact_planner.h"
#include "search_node.h"
#include "step_failure.h"

namespace rbcp::contact_planner_detail {

/// The most informative failure of a search: the one furthest along the path.
struct Failure {
  double t = -1.0;  ///< path time [s]; -1 while there is none
  int leg = -1;     ///< Index(Leg) of the leg that could not step; -1 while there is none
  /// What failed: the keep phase's stop (the leg must step there) or the leg's step; none while
  /// there is none.
  std::variant<std::monostate, KeepStop, StepFailure> what;

  /// Keeps `other` when it lies at least as far along the path (the later of two at one time).
  void Note(Failure other) {
    if (other.t >= t) *this = std::move(other);
  }
  /// "no valid step for LF at path time 2.84 s: <what>".
  std::string Describe() const;
};

/// Searches for steps from `root` along `path` with the crawl `profile`, to the goal or, with
/// max_steps >= 0, for at most max_steps steps. The result's plan, status, reason, failure time
/// and leg; the caller sets the planning time and the stats.
/// With `path_to_furthest` set, it receives the states (as unexpanded nodes) from the root to
/// the node that got furthest along the path.
ContactPlanResult Search(const PlannerContext& ctx, const PathTrack& path, const CrawlProfile& profile, Node root,
                         int max_steps, std::vector<Node>* path_to_furthest = nullptr);

/// Search() with gait_advance_s and base_shift.keep_fraction; when that fails for want of
/// footholds (not time), again with each of retry.keep_fraction, then with each of
/// retry.gait_advance_s (each with the kept fractions in the same order), while the evaluation
/// bound and the time budget last: first from the state retry.restart_back_s of path time before
/// the furthest point of the failed search (its steps up to there kept), then from the root. The
/// crawl timing and the body's path between swings decide where every foot stands when the
/// terrain gets hard, so a dead end under one profile is rarely one under another.
/// The searches run one after another, or, with `spare` LP workspaces, on 1 + spare.size()
/// threads (the query's workspace and the spare ones), each taking the next search not yet
/// started, the later ones ahead of their turn: the answer is the first in the order above
/// that finds a plan, with the work counted up to it, so the plan and its stats do not depend on
/// the threads.
ContactPlanResult SearchWithRetries(const PlannerContext& ctx, const PathTrack& path, const Node& root, int max_steps,
                                    const std::vector<StaticEquilibrium*>& spare = {});

}  // namespace rbcp::contact_planner_detail
