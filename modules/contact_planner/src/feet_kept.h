#pragma once
/// The keep phase: the trunk advances along the path with the four feet kept in place, until a
/// foot can no longer be kept or the path ends.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "path_track.h"
#include "planner_context.h"
#include "search_node.h"
#include "stance_checks.h"

namespace rbcp::contact_planner_detail {

/// Why the feet cannot be kept at a path time, or why the trunk stops advancing on them.
struct KeepStop {
  enum class Kind {
    kLeg,         ///< `leg` cannot be kept: leg_failure says how
    kBody,        ///< the trunk collides, or the CoM is near the edge of the support polygon
    kTimeBudget,  ///< the query's time budget ran out
  };
  Kind kind = Kind::kLeg;
  Leg leg = Leg::kLF;                            ///< kLeg
  KeepFailure leg_failure = KeepFailure::kNone;  ///< kLeg

  /// "LF leaves its workspace", "trunk collision or CoM near the edge of the support polygon", ...
  std::string Describe() const;
};

/// The four feet tested with the base at one path time.
struct KeepCheck {
  std::array<bool, kNumLegs> failing{};   ///< per leg; all when the trunk or the support failed
  std::array<double, kNumLegs> stretch{};  ///< per leg, largest workspace ratio
  std::optional<KeepStop> failure;         ///< what failed first; nullopt when every foot is kept
  bool ok() const { return !failure; }
};

/// Tests the node's four feet (KeepLeg), then the trunk's collision and the CoM's support margin,
/// with the base at path time t (the node's shift, the base pose following its feet).
KeepCheck KeepAt(const PlannerContext& ctx, const PathTrack& path, const Node& node, double t);

struct LegRank {
  Leg leg;
  double stretch;  ///< largest workspace ratio (> 1 outside)
  bool failing;
};

/// How far the trunk advances along the path with the node's feet kept.
struct KeptFeetAdvance {
  bool reached_end = false;      ///< the feet are kept to the path end
  double t_last_keepable = 0.0;  ///< the last path time at which every foot can be kept
  std::vector<LegRank> ranking;  ///< all four legs: failing legs first, by stretch, then kTieOrder
  std::optional<KeepStop> stop;  ///< what failed first after t_last_keepable; nullopt at the path end
};

/// The keep phase: advances from node.t in steps of path_step_s while KeepAt holds, then bisects
/// down to step_time_resolution_s to the last time it holds. Stops where it is, every leg
/// failing, once the query's time budget is exhausted.
KeptFeetAdvance AdvanceWithFeetKept(const PlannerContext& ctx, const PathTrack& path, const Node& node);

}  // namespace rbcp::contact_planner_detail
