#include "convex_primitives.h"

#include <algorithm>
#include <cmath>

namespace rbcp::limb_database_detail {
namespace {

/// Added to the absolute rotation terms of the separating-axis test so that nearly parallel
/// edges (whose cross product is almost zero) cannot report a false separation.
constexpr double kParallelEpsilon = 1e-9;

double PointBoxDistanceLocal(const Eigen::Vector3d& p_box, const Eigen::Vector3d& half) {
  const Eigen::Vector3d outside = (p_box.cwiseAbs() - half).cwiseMax(0.0);
  return outside.norm();
}

}  // namespace

double ConvexPrimitive::BoundingRadius() const {
  switch (kind) {
    case Kind::kSphere:
      return radius;
    case Kind::kCapsule:
      return half.z() + radius;
    case Kind::kBox:
      return half.norm();
    case Kind::kCylinder:
      return std::hypot(half.z(), radius);
  }
  return 0.0;
}

double PointBoxDistance(const Eigen::Vector3d& p, const ConvexPrimitive& box) {
  return PointBoxDistanceLocal(box.axes.transpose() * (p - box.centre), box.half);
}

double SegmentBoxDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const ConvexPrimitive& box) {
  // The distance to a convex set is convex along the segment: golden-section search on t.
  const Eigen::Vector3d a_box = box.axes.transpose() * (a - box.centre);
  const Eigen::Vector3d d_box = box.axes.transpose() * (b - a);
  auto f = [&](double t) { return PointBoxDistanceLocal(a_box + t * d_box, box.half); };
  const double length = d_box.norm();
  constexpr double kInvPhi = 0.6180339887498949;
  double lo = 0.0;
  double hi = 1.0;
  double x1 = hi - kInvPhi * (hi - lo);
  double x2 = lo + kInvPhi * (hi - lo);
  double f1 = f(x1);
  double f2 = f(x2);
  // Stop once the bracket is shorter than 1e-10 m along the segment (f is 1-Lipschitz in metres).
  for (int it = 0; it < 100 && (hi - lo) * length > 1e-10; ++it) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kInvPhi * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kInvPhi * (hi - lo);
      f2 = f(x2);
    }
  }
  return std::min({f(0.0), f(1.0), f1, f2});
}

bool BoxesOverlap(const ConvexPrimitive& a, const ConvexPrimitive& b) {
  // Separating-axis test (Ericson, Real-Time Collision Detection, 4.4.1); touching counts as separated.
  const Eigen::Matrix3d R = a.axes.transpose() * b.axes;
  const Eigen::Matrix3d abs_R = R.cwiseAbs().array() + kParallelEpsilon;
  const Eigen::Vector3d t = a.axes.transpose() * (b.centre - a.centre);
  const Eigen::Vector3d& ea = a.half;
  const Eigen::Vector3d& eb = b.half;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(t[i]) >= ea[i] + abs_R.row(i).dot(eb)) return false;
  }
  for (int j = 0; j < 3; ++j) {
    if (std::abs(t.dot(R.col(j))) >= abs_R.col(j).dot(ea) + eb[j]) return false;
  }
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3;
    const int i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3;
      const int j2 = (j + 2) % 3;
      const double ra = ea[i1] * abs_R(i2, j) + ea[i2] * abs_R(i1, j);
      const double rb = eb[j1] * abs_R(i, j2) + eb[j2] * abs_R(i, j1);
      if (std::abs(t[i2] * R(i1, j) - t[i1] * R(i2, j)) >= ra + rb) return false;
    }
  }
  return true;
}

namespace {

ConvexPrimitive CylinderCapsule(const ConvexPrimitive& cylinder) {
  ConvexPrimitive p = cylinder;
  p.kind = ConvexPrimitive::Kind::kCapsule;
  return p;
}

ConvexPrimitive CylinderBox(const ConvexPrimitive& cylinder) {
  ConvexPrimitive p = cylinder;
  p.kind = ConvexPrimitive::Kind::kBox;
  p.half = Eigen::Vector3d(cylinder.radius, cylinder.radius, cylinder.half.z());
  p.radius = 0.0;
  return p;
}

}  // namespace

bool PrimitivesOverlap(const ConvexPrimitive& a, const ConvexPrimitive& b) {
  using Kind = ConvexPrimitive::Kind;
  if ((a.centre - b.centre).norm() >= a.BoundingRadius() + b.BoundingRadius()) return false;
  if (a.kind == Kind::kCylinder) {
    return PrimitivesOverlap(CylinderCapsule(a), b) && PrimitivesOverlap(CylinderBox(a), b);
  }
  if (b.kind == Kind::kCylinder) {
    return PrimitivesOverlap(a, CylinderCapsule(b)) && PrimitivesOverlap(a, CylinderBox(b));
  }
  if (static_cast<int>(a.kind) > static_cast<int>(b.kind)) return PrimitivesOverlap(b, a);
  const double r = a.radius + b.radius;
  switch (a.kind) {
    case Kind::kSphere:
      switch (b.kind) {
        case Kind::kSphere:
          return (a.centre - b.centre).norm() < r;
        case Kind::kCapsule:
          return PointSegmentDistance(a.centre, b.SegmentStart(), b.SegmentEnd()) < r;
        case Kind::kBox:
          return PointBoxDistance(a.centre, b) < r;
        case Kind::kCylinder:
          break;
      }
      break;
    case Kind::kCapsule:
      switch (b.kind) {
        case Kind::kCapsule:
          return SegmentSegmentDistance(a.SegmentStart(), a.SegmentEnd(), b.SegmentStart(), b.SegmentEnd()) < r;
        case Kind::kBox:
          return SegmentBoxDistance(a.SegmentStart(), a.SegmentEnd(), b) < r;
        case Kind::kSphere:
        case Kind::kCylinder:
          break;
      }
      break;
    case Kind::kBox:
      return BoxesOverlap(a, b);
    case Kind::kCylinder:
      break;
  }
  return false;
}

}  // namespace rbcp::limb_database_detail
