#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping {
namespace {

/// Parameter interval [lo, hi] of a line; empty when lo > hi.
struct Interval {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool Empty() const { return lo > hi; }
  void Intersect(double a, double b) {
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
  }
};

constexpr double kParallel = 1e-12;

/// The line o + t d within the slab |x_axis| <= half.
void Slab(double o, double d, double half, Interval* in) {
  if (std::abs(d) < kParallel) {
    if (std::abs(o) > half) *in = Interval{1.0, 0.0};
    return;
  }
  in->Intersect((-half - o) / d, (half - o) / d);
}

/// The line o + t d within the quadric a t^2 + b t + c <= 0 (a >= 0).
void InsideQuadric(double a, double b, double c, Interval* in) {
  if (a < kParallel) {
    if (c > 0.0) *in = Interval{1.0, 0.0};  // parallel to the axis, outside the radius
    return;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) {
    *in = Interval{1.0, 0.0};
    return;
  }
  const double root = std::sqrt(disc);
  in->Intersect((-b - root) / (2.0 * a), (-b + root) / (2.0 * a));
}

}  // namespace

std::optional<double> LowestPointOver(const BodySolid& solid, const Eigen::Vector2d& xy) {
  // The vertical line (xy, 0) + t e_z in the solid's frame: o + t d, t the world z.
  const Eigen::Matrix3d R = solid.pose_W.linear();
  const Eigen::Vector3d o = R.transpose() * (Eigen::Vector3d(xy.x(), xy.y(), 0.0) - solid.pose_W.translation());
  const Eigen::Vector3d d = R.transpose().col(2);
  Interval in;
  switch (solid.kind) {
    case BodySolid::Kind::kBox:
      for (int i = 0; i < 3; ++i) Slab(o[i], d[i], solid.half_extents[i], &in);
      break;
    case BodySolid::Kind::kCylinder:
      Slab(o.z(), d.z(), solid.half_length, &in);
      InsideQuadric(d.head<2>().squaredNorm(), 2.0 * o.head<2>().dot(d.head<2>()),
                    o.head<2>().squaredNorm() - solid.radius * solid.radius, &in);
      break;
    case BodySolid::Kind::kSphere:
      InsideQuadric(1.0, 2.0 * o.dot(d), o.squaredNorm() - solid.radius * solid.radius, &in);
      break;
  }
  if (in.Empty()) return std::nullopt;
  return in.lo;
}

std::pair<Eigen::Vector2d, Eigen::Vector2d> FootprintBox(const BodySolid& solid) {
  const Eigen::Matrix3d R = solid.pose_W.linear();
  Eigen::Vector2d extent;
  for (int i = 0; i < 2; ++i) {
    switch (solid.kind) {
      case BodySolid::Kind::kBox:
        extent[i] = R.row(i).cwiseAbs().dot(solid.half_extents);
        break;
      case BodySolid::Kind::kCylinder: {
        const double axis = std::abs(R(i, 2));
        extent[i] = axis * solid.half_length + solid.radius * std::sqrt(std::max(0.0, 1.0 - axis * axis));
        break;
      }
      case BodySolid::Kind::kSphere:
        extent[i] = solid.radius;
        break;
    }
  }
  const Eigen::Vector2d c = solid.pose_W.translation().head<2>();
  return {c - extent, c + extent};
}

}  // namespace rbcp::mapping
