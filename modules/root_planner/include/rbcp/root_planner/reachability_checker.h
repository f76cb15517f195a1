#pragma once
/// The reachability condition of RB-PRM for a root pose (position and yaw; the trunk is kept
/// level): the trunk shape is collision-free with the terrain and every leg's range-of-motion
/// shape (ROM) intersects at least one contact surface.

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/leg.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/root_planner/convex_polytope.h"

namespace rbcp {

/// Outcome of one reachability test.
struct ReachabilityReport {
  bool trunk_collision = false;  ///< the trunk shape touches the terrain or its centre is inside a solid
  /// Per leg (LF, RF, LH, RH): the index of a contact surface its ROM intersects, or -1.
  std::array<int, kNumLegs> leg_surface{{-1, -1, -1, -1}};

  bool LegInReach(Leg leg) const { return leg_surface[static_cast<std::size_t>(Index(leg))] >= 0; }
  bool Valid() const;
  /// Empty when valid, otherwise e.g. "trunk collides with the terrain" or "no contact surface in
  /// reach of LF, RH".
  std::string Reason() const;
};

/// Tests root poses against one terrain and its contact surfaces. Queries reuse internal
/// collision objects: one checker per thread. Answers depend only on the pose.
class ReachabilityChecker {
 public:
  /// `terrain` and `surfaces` are in the world frame; `roms` (LF, RF, LH, RH) and `trunk` in the
  /// base frame. Each surface becomes a convex prism of depth `surface_depth` [m] below its
  /// polygon. Throws InputError for an empty or invalid terrain mesh or a degenerate surface.
  ReachabilityChecker(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                      const std::array<ConvexPolytope, kNumLegs>& roms, const ConvexPolytope& trunk,
                      double surface_depth = 0.005);
  ~ReachabilityChecker();
  ReachabilityChecker(ReachabilityChecker&&) noexcept;
  ReachabilityChecker& operator=(ReachabilityChecker&&) noexcept;

  /// The condition for the base at p_W [m] with heading yaw [rad] (roll and pitch zero).
  bool IsValid(const Eigen::Vector3d& p_W, double yaw);
  /// Full diagnosis: every condition is evaluated (no early exit).
  ReachabilityReport Check(const Eigen::Vector3d& p_W, double yaw);
  /// Only the trunk part of the condition.
  bool TrunkCollides(const Eigen::Vector3d& p_W, double yaw);

  /// Number of IsValid/Check calls so far.
  long Queries() const;
  std::size_t NumSurfaces() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbcp
