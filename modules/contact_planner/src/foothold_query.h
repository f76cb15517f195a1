#pragma once
/// New footholds from the limb database: the samples near the contact surfaces in a leg's
/// workspace, projected onto their surface, ranked against a target and deduplicated.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "planner_context.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/core/leg.h"

namespace rbcp::contact_planner_detail {

/// A foothold proposed by the database.
struct Candidate {
  int surface = -1;  ///< index into PlannerContext::surfaces
  int sample = -1;   ///< the database sample of the leg
  double score = 0.0;  ///< higher is better
  Eigen::Vector3d foothold = Eigen::Vector3d::Zero();  ///< on the surface, world frame
};

/// Database candidates for `leg` with the base at base_W, on the surfaces around the leg's
/// workspace (with near_half > 0 only within near_half of target_W in x and y), ranked by
/// distance to target_W (in the heading frame of target_yaw) and offline score, best first, and
/// deduplicated by projected foothold (the best of each FootholdCell). Counts the raw candidates in the stats.
/// Once the query's time budget is exhausted it stops going through the surfaces: the caller
/// checks the budget before it takes the list as complete.
std::vector<Candidate> RankedCandidates(const PlannerContext& ctx, Leg leg, const Eigen::Isometry3d& base_W,
                                        const Eigen::Vector3d& target_W, double target_yaw, double near_half = 0.0);

/// The (x, y) indices of the grid cell of size `cell` [m] holding the foothold.
Eigen::Matrix<long long, 2, 1> FootholdCellXy(const Eigen::Vector3d& foothold, double cell);

/// Key of the candidate's grid cell of size `cell` [m] (foothold x and y) on its surface: the
/// candidates of one cell are one foothold.
long long FootholdCell(const Candidate& c, double cell);

/// True when p is at least the minimum foot separation (horizontally) from every foot marked in
/// `among`.
bool FarEnoughFromFeet(const PlannerContext& ctx, const std::array<FootContact, kNumLegs>& feet,
                       const std::array<bool, kNumLegs>& among, const Eigen::Vector3d& p);
/// The same from every foot but `skip`.
bool FarEnoughFromFeet(const PlannerContext& ctx, const std::array<FootContact, kNumLegs>& feet, int skip,
                       const Eigen::Vector3d& p);

}  // namespace rbcp::contact_planner_detail
