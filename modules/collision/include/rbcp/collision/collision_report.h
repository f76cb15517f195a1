#pragma once
/// The outcome of a collision query (RobotTerrainCollision, RobotSelfCollision).

#include <string>

namespace rbcp {

/// Outcome of a collision query. When several shapes collide, the first in checking order is
/// reported. Terrain: trunk shapes, then the legs LF, RF, LH, RH, each from hip to foot, in the
/// order of RobotModel::CollisionShapes(). Self: for each leg in turn, its shapes against the
/// trunk's, then against each later leg's.
struct CollisionReport {
  bool collision = false;
  std::string first_shape;  ///< URDF collision name of the robot shape (the link name if unnamed)
  /// "terrain", or for self-collision the other robot shape's name (e.g. "LH_shank").
  std::string obstacle;
  /// Depth [m] of the deepest contact FCL reports between the two (the shortest translation
  /// separating the shape from one terrain triangle or from the other shape). For a stance foot,
  /// the depth of the full sphere. For a shape enclosed by the terrain: the vertical distance from
  /// its centre up to the nearest upward-facing terrain triangle above it.
  double penetration = 0.0;
};

}  // namespace rbcp
