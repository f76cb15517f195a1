#pragma once
/// Which contact surfaces a legged robot can pass between. Two surfaces are joined when a point
/// of one lies within max_gap_m of a point of the other: a step (or the span of the robot's
/// stance) bridges the gap. Surfaces joined through a chain of such gaps form one component; a
/// goal whose surfaces lie in no component of the start's cannot be reached by any sequence of
/// footholds, whatever the planners try, so the question is answered before any search.

#include <Eigen/Core>
#include <vector>

#include "rbcp/core/affordance_surface.h"

namespace rbcp {

/// Least distance [m] between a point and a convex polygon (its plane region, not its outline).
double PointPolygonDistance(const Eigen::Vector3d& p, const AffordanceSurface& surface);
/// Least distance [m] between two convex polygons.
double PolygonDistance(const AffordanceSurface& a, const AffordanceSurface& b);

class SurfaceGraph {
 public:
  /// Joins every pair of surfaces at most max_gap_m apart. Quadratic in the number of surfaces,
  /// with a bounding-box test before every exact distance.
  SurfaceGraph(const std::vector<AffordanceSurface>& surfaces, double max_gap_m);

  /// Indices of the surfaces with a point within radius_m of `point`.
  std::vector<int> SurfacesNear(const Eigen::Vector3d& point, double radius_m) const;
  /// True when some surface of `from` and some surface of `to` are in one component.
  bool Joined(const std::vector<int>& from, const std::vector<int>& to) const;
  /// Component index of every surface (components numbered from 0).
  const std::vector<int>& Components() const { return component_; }
  int ComponentCount() const { return components_; }

 private:
  std::vector<AffordanceSurface> surfaces_;
  std::vector<Eigen::Vector3d> lo_, hi_;  // bounding boxes
  std::vector<int> component_;
  int components_ = 0;
};

}  // namespace rbcp
