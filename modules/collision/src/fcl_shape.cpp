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

}  // namespace

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

bool FclCollide(const FclShape& a, const Eigen::Isometry3d& Ta, const FclShape& b, const Eigen::Isometry3d& Tb,
                fcl::CollisionResultd& result) {
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
