#pragma once
/// The keep phase: the trunk advances along the path with the four feet kept in place, until a
/// foot can no longer be kept or the path ends.

#include <array>
#include <string>
#include <vector>

#include "path_track.h"
#include "planner_context.h"
#include "search_node.h"

namespace rbcp::contact_planner_detail {

/// The four feet tested with the base at one path time.
struct KeepCheck {
  bool ok = false;
  std::array<bool, kNumLegs> failing{};   ///< per leg; all when the trunk or the support failed
  std::array<double, kNumLegs> stretch{};  ///< per leg, largest workspace ratio
  std::string why;                         ///< what failed first (empty when ok)
};

/// Tests the node's four feet (KeepLeg), then the trunk's collision and the CoM's support margin,
/// with the base at path time t (the node's shift, the base pose following its feet).
KeepCheck KeepAt(const PlannerContext& ctx, const PathTrack& path, const Node& node, double t);

struct LegRank {
  Leg leg;
  double stretch;  ///< largest workspace ratio (> 1 outside)
  bool failing;
};

struct KeepResult {
  bool reached_end = false;
  double t_good = 0.0;           ///< the last path time at which every foot can be kept
  std::vector<LegRank> ranking;  ///< all four legs: failing legs first, by stretch, then kTieOrder
  std::string why;               ///< what failed first
};

/// Advances from node.t in steps of path_step_s while KeepAt holds, then bisects down to
/// step_time_resolution_s to the last time it holds. Stops where it is, every leg failing, once
/// the query's time budget is exhausted.
KeepResult KeepPhase(const PlannerContext& ctx, const PathTrack& path, const Node& node);

}  // namespace rbcp::contact_planner_detail
