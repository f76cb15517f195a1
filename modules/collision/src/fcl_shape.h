#pragma once
// A robot collision primitive as FCL geometry, with the bounds and support distances the broad
// phases use, and the exact test of two placed primitives. Private to the collision library.

#include <fcl/geometry/collision_geometry.h>
#include <fcl/narrowphase/collision_result.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>

#include "rbcp/collision/robot_collision_model.h"
#include "terrain_grid.h"

namespace rbcp::collision_detail {

// One collision primitive placed on a link.
struct FclShape {
  std::string name;
  int link_index = -1;
  CollisionShape::Kind kind = CollisionShape::Kind::kBox;
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // box
  double radius = 0.0;                                     // cylinder, sphere
  double half_length = 0.0;                                // cylinder
  Eigen::Isometry3d pose_link = Eigen::Isometry3d::Identity();
  std::shared_ptr<fcl::CollisionGeometryd> geometry;

  // The primitive with its geometry.
  static FclShape From(const CollisionPrimitive& p);
  // (Re)builds `geometry` from the kind and sizes.
  void MakeGeometry();
  // Half the shape's extent along the unit direction n at pose T.
  double Support(const Eigen::Isometry3d& T, const Eigen::Vector3d& n) const;
  // Directions along which the shape has faces or an axis at pose T: a box's three face normals,
  // a cylinder's axis, none for a sphere. Returns how many of axes[] it filled.
  int Axes(const Eigen::Isometry3d& T, std::array<Eigen::Vector3d, 3>& axes) const;
  // Axis-aligned bounds of the shape at pose T.
  Aabb Bounds(const Eigen::Isometry3d& T) const;
};

// Gap [m] by which a separating axis must part two convex sets before the GJK test is skipped:
// touching and nearly touching pairs are left to GJK and its own tolerance, so the pre-tests
// never change a verdict.
inline constexpr double kSeparationSlack = 1e-5;

// Whether two placed shapes touch: their bounds (box_a, box_b at poses Ta, Tb), the separating
// axes of Separated, then FCL's narrow phase (libccd). `result` is scratch space.
bool ShapesTouch(const FclShape& a, const Eigen::Isometry3d& Ta, const Aabb& box_a, const FclShape& b,
                 const Eigen::Isometry3d& Tb, const Aabb& box_b, fcl::CollisionResultd& result);
// The depth [m] of the deepest contact FCL reports between two touching shapes.
double ShapesDepth(const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b, const Eigen::Isometry3d& Tb,
                   fcl::CollisionResultd& result);

}  // namespace rbcp::collision_detail
