#pragma once
/// The standing stance a query starts from.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "planner_context.h"
#include "rbcp/core/contact_plan.h"

namespace rbcp::contact_planner_detail {

/// A standing stance, or why there is none.
struct StandingResult {
  std::optional<WholeBodyState> state;
  std::string why;         ///< empty with a state
  bool timed_out = false;  ///< the query's time budget ended the search for it
};

/// The standing stance with the base level at base_position heading `yaw`: for each leg in
/// kTieOrder, the best database foothold near the reference foot position below the hip that is
/// kept (KeepLeg) and apart from the feet placed before; then no trunk or self-collision, static
/// equilibrium, the support margin and the torques.
StandingResult StandingAt(const PlannerContext& ctx, const Eigen::Vector3d& base_position, double yaw);

}  // namespace rbcp::contact_planner_detail
