#pragma once
// Overlap tests between posed convex primitives (spheres, capsules, oriented boxes, cylinders),
// used by the leg self-collision filter of the limb database. All quantities are in one common
// frame [m].
//
// Cylinders are tested through the two convex sets whose intersection they are: the capsule with
// the same axis and radius, and the box that bounds the cylinder. A cylinder is reported to
// overlap another shape only when both of these do. That is necessary for a true overlap, so the
// test never misses a collision; it may report one only where the other shape reaches into both a
// capsule cap and a box corner at the same time.

#include <Eigen/Core>

#include "rbcp/core/segment_distance.h"

namespace rbcp::limb_database_detail {

/// A posed sphere, capsule or oriented box.
struct ConvexPrimitive {
  enum class Kind { kSphere, kCapsule, kBox, kCylinder };
  Kind kind = Kind::kSphere;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  /// Columns are the primitive's axes (box: x, y, z; capsule and cylinder: axis along column 2).
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  /// Box: half extents along the axes. Capsule, cylinder: z() is half the segment/axis length.
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  /// Sphere, capsule and cylinder radius (0 for boxes).
  double radius = 0.0;

  /// Radius of a sphere about `centre` that contains the primitive.
  double BoundingRadius() const;
  /// Capsule segment (cylinder axis) end points.
  Eigen::Vector3d SegmentStart() const { return centre - half.z() * axes.col(2); }
  Eigen::Vector3d SegmentEnd() const { return centre + half.z() * axes.col(2); }
};

/// Distance from point p to a solid box (0 inside).
double PointBoxDistance(const Eigen::Vector3d& p, const ConvexPrimitive& box);
/// Distance from the closed segment [a, b] to a solid box (0 when they intersect), to 1e-9 m.
double SegmentBoxDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const ConvexPrimitive& box);
/// True when two solid boxes share interior points (separating-axis test over 15 axes, each
/// rotation term padded by 1e-9 so that nearly parallel edges never separate falsely).
bool BoxesOverlap(const ConvexPrimitive& a, const ConvexPrimitive& b);

/// True when the two solids share interior points. Surfaces that touch within about 1e-9 m may
/// count either way.
bool PrimitivesOverlap(const ConvexPrimitive& a, const ConvexPrimitive& b);

}  // namespace rbcp::limb_database_detail
