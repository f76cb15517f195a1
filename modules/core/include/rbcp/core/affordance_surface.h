#pragma once
/// A contact surface: where a foot may be placed. Made by the affordance extractor, read by the
/// root planner, the contact planner, the plan checker and the transport layer.

#include <Eigen/Core>
#include <vector>

namespace rbcp {

/// One contact surface.
struct AffordanceSurface {
  /// Convex polygon, counter-clockwise seen from the normal side, world frame [m].
  std::vector<Eigen::Vector3d> vertices;
  /// Unit plane normal, world frame, pointing out of the terrain.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  /// Area of the (eroded) polygon [m^2].
  double area = 0.0;
};

}  // namespace rbcp
