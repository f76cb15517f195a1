#pragma once
// A robot collision primitive as FCL geometry, with the bounds and support distances the broad
// phases use, and the exact test of two placed primitives. Private to the collision library. The
// cheap tests are inline: the broad phases call them for every candidate pair.

#include <fcl/geometry/collision_geometry.h>
#include <fcl/narrowphase/collision_result.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "rbcp/collision/robot_collision_model.h"
#include "terrain_grid.h"

namespace rbcp::collision_detail {

// One collision primitive with its FCL geometry.
struct FclShape : CollisionPrimitive {
  std::shared_ptr<fcl::CollisionGeometryd> geometry;

  explicit FclShape(const CollisionPrimitive& p) : CollisionPrimitive(p) { MakeGeometry(); }
  // (Re)builds `geometry` from the kind and sizes.
  void MakeGeometry();

  // Half the shape's extent along the unit direction n at pose T.
  double Support(const Eigen::Isometry3d& T, const Eigen::Vector3d& n) const {
    switch (kind) {
      case CollisionShape::Kind::kBox:
        return (T.linear().transpose() * n).cwiseAbs().dot(half_extents);
      case CollisionShape::Kind::kCylinder: {
        const double c = std::abs(n.dot(T.linear().col(2)));
        return c * half_length + radius * std::sqrt(std::max(0.0, 1.0 - c * c));
      }
      case CollisionShape::Kind::kSphere:
      default:
        return radius;
    }
  }

  // Directions along which the shape has faces or an axis at pose T: a box's three face normals,
  // a cylinder's axis, none for a sphere. Returns how many of axes[] it filled.
  int Axes(const Eigen::Isometry3d& T, std::array<Eigen::Vector3d, 3>& axes) const {
    switch (kind) {
      case CollisionShape::Kind::kBox:
        for (int i = 0; i < 3; ++i) axes[static_cast<std::size_t>(i)] = T.linear().col(i);
        return 3;
      case CollisionShape::Kind::kCylinder:
        axes[0] = T.linear().col(2);
        return 1;
      case CollisionShape::Kind::kSphere:
      default:
        return 0;
    }
  }

  // Axis-aligned bounds of the shape at pose T.
  Aabb Bounds(const Eigen::Isometry3d& T) const {
    const Eigen::Vector3d c = T.translation();
    Eigen::Vector3d e;
    switch (kind) {
      case CollisionShape::Kind::kBox:
        e = T.linear().cwiseAbs() * half_extents;
        break;
      case CollisionShape::Kind::kCylinder: {
        const Eigen::Vector3d axis = T.linear().col(2);
        for (int i = 0; i < 3; ++i) {
          e[i] = std::abs(axis[i]) * half_length + radius * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i]));
        }
        break;
      }
      case CollisionShape::Kind::kSphere:
      default:
        e.setConstant(radius);
        break;
    }
    return Aabb{c - e, c + e};
  }
};

// Gap [m] by which a separating axis must part two convex sets before the GJK test is skipped:
// touching and nearly touching pairs are left to GJK and its own tolerance, so the pre-tests
// never change a verdict.
inline constexpr double kSeparationSlack = 1e-5;

// True when the unit axis n separates the shapes a (at Ta) and b (at Tb) by more than the slack.
inline bool ApartAlong(const Eigen::Vector3d& n, const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b,
                       const Eigen::Isometry3d& Tb) {
  return std::abs(n.dot(Tb.translation() - Ta.translation())) > a.Support(Ta, n) + b.Support(Tb, n) + kSeparationSlack;
}

// A cheap sufficient test that two placed shapes do not touch: the line through their centres,
// the box face normals and the cylinder axes as separating axes (exact shapes, no tolerance).
inline bool Separated(const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b, const Eigen::Isometry3d& Tb) {
  const Eigen::Vector3d d = Tb.translation() - Ta.translation();
  const double length = d.norm();
  if (length > 1e-12 && ApartAlong(d / length, a, Ta, b, Tb)) return true;
  std::array<Eigen::Vector3d, 3> axes;
  for (int k = a.Axes(Ta, axes) - 1; k >= 0; --k) {
    if (ApartAlong(axes[static_cast<std::size_t>(k)], a, Ta, b, Tb)) return true;
  }
  for (int k = b.Axes(Tb, axes) - 1; k >= 0; --k) {
    if (ApartAlong(axes[static_cast<std::size_t>(k)], a, Ta, b, Tb)) return true;
  }
  return false;
}

// FCL's narrow phase (libccd) on two placed shapes: whether they touch. `result` is scratch space.
bool FclCollide(const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b, const Eigen::Isometry3d& Tb,
                fcl::CollisionResultd& result);

// Whether two placed shapes touch: their bounds (box_a, box_b at poses Ta, Tb), the separating
// axes of Separated, then FCL's narrow phase.
inline bool ShapesTouch(const FclShape& a, const Eigen::Isometry3d& Ta, const Aabb& box_a, const FclShape& b,
                        const Eigen::Isometry3d& Tb, const Aabb& box_b, fcl::CollisionResultd& result) {
  if (!box_a.Overlaps(box_b)) return false;
  if (Separated(a, Ta, b, Tb)) return false;
  return FclCollide(a, Ta, b, Tb, result);
}

// The depth [m] of the deepest contact FCL reports between two touching shapes.
double ShapesDepth(const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b, const Eigen::Isometry3d& Tb,
                   fcl::CollisionResultd& result);

}  // namespace rbcp::collision_detail
