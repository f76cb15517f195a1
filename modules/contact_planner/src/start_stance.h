#pragma once
/// The standing stance a query starts from.

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>

#include "planner_context.h"
#include "rbcp/collision/robot_terrain_collision.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/stance/stance_checker.h"

namespace rbcp::contact_planner_detail {

/// Why there is no standing stance.
struct StandingFailure {
  enum class Kind {
    kTimeBudget,      ///< the query's time budget ended the search for it
    kNoFoothold,      ///< none of `candidates` near `leg`'s reference position is kept
    kTrunkCollision,  ///< the trunk collides with the terrain
    kSelfCollision,   ///< `collision`'s shapes touch
    kUnstable,        ///< static equilibrium below the robustness threshold (robustness_N)
    kSupport,         ///< the CoM too near the support polygon's edge (verdict)
    kTorque,          ///< a joint above the torque ceiling (verdict)
  };
  explicit StandingFailure(Kind kind, StanceVerdict verdict = {}) : kind(kind), verdict(std::move(verdict)) {}

  Kind kind;
  StanceVerdict verdict;       ///< kSupport, kTorque
  Leg leg = Leg::kLF;          ///< kNoFoothold
  std::size_t candidates = 0;  ///< kNoFoothold
  CollisionReport collision;   ///< kSelfCollision
  double robustness_N = 0.0;   ///< kUnstable [N]

  /// E.g. "no valid foothold for LF near its reference position (12 candidates)".
  std::string Describe() const;
};

/// A standing stance, or why there is none.
struct StandingResult {
  std::optional<WholeBodyState> state;
  std::optional<StandingFailure> failure;  ///< set without a state
};

/// The standing stance with the base level at base_position heading `yaw`: for each leg in
/// kTieOrder, the best database foothold near the reference foot position below the hip that is
/// kept (KeepLeg) and apart from the feet placed before; then no trunk or self-collision, static
/// equilibrium, the support margin and the torques.
StandingResult StandingAt(const PlannerContext& ctx, const Eigen::Vector3d& base_position, double yaw);

}  // namespace rbcp::contact_planner_detail
