#include "fcl_shape.h"

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <cmath>

namespace rbcp::collision_detail {
namespace {

// libccd: faster than FCL's own GJK on these primitive tests, and it measures depth only on request.
constexpr fcl::GJKSolverType kSolver = fcl::GST_LIBCCD;

// True when the unit axis n separates the shapes a (at Ta) and b (at Tb) by more than the slack.
bool ApartAlong(const Eigen::Vector3d& n, const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b,
                const Eigen::Isometry3d& Tb) {
  return std::abs(n.dot(Tb.translation() - Ta.translation())) > a.Support(Ta, n) + b.Support(Tb, n) + kSeparationSlack;
}

// A cheap sufficient test that two placed shapes do not touch: the line through their centres,
// the box face normals and the cylinder axes as separating axes (exact shapes, no tolerance).
bool Separated(const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b, const Eigen::Isometry3d& Tb) {
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

}  // namespace

FclShape FclShape::From(const CollisionPrimitive& p) {
  FclShape s;
  s.name = p.name;
  s.link_index = p.link_index;
  s.kind = p.kind;
  s.half_extents = p.half_extents;
  s.radius = p.radius;
  s.half_length = p.half_length;
  s.pose_link = p.pose_link;
  s.MakeGeometry();
  return s;
}

void FclShape::MakeGeometry() {
  switch (kind) {
    case CollisionShape::Kind::kBox:
      geometry = std::make_shared<fcl::Boxd>(2.0 * half_extents);
      break;
    case CollisionShape::Kind::kCylinder:
      geometry = std::make_shared<fcl::Cylinderd>(radius, 2.0 * half_length);
      break;
    case CollisionShape::Kind::kSphere:
      geometry = std::make_shared<fcl::Sphered>(radius);
      break;
  }
}

double FclShape::Support(const Eigen::Isometry3d& T, const Eigen::Vector3d& n) const {
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

int FclShape::Axes(const Eigen::Isometry3d& T, std::array<Eigen::Vector3d, 3>& axes) const {
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

Aabb FclShape::Bounds(const Eigen::Isometry3d& T) const {
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

bool ShapesTouch(const FclShape& a, const Eigen::Isometry3d& Ta, const Aabb& box_a, const FclShape& b,
                 const Eigen::Isometry3d& Tb, const Aabb& box_b, fcl::CollisionResultd& result) {
  if (!box_a.Overlaps(box_b)) return false;
  if (Separated(a, Ta, b, Tb)) return false;
  fcl::CollisionRequestd request(1, false);
  request.gjk_solver_type = kSolver;
  result.clear();
  return fcl::collide(a.geometry.get(), Ta, b.geometry.get(), Tb, request, result) > 0;
}

double ShapesDepth(const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b, const Eigen::Isometry3d& Tb,
                   fcl::CollisionResultd& result) {
  fcl::CollisionRequestd request(1, true);
  request.gjk_solver_type = kSolver;
  result.clear();
  fcl::collide(a.geometry.get(), Ta, b.geometry.get(), Tb, request, result);
  return result.numContacts() > 0 ? std::abs(result.getContact(0).penetration_depth) : 0.0;
}

}  // namespace rbcp::collision_detail
