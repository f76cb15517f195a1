#pragma once
/// The trunk's collision shape for root planning: a box with a keel under the belly.
///
/// Seen from the side, the bottom is a "V": the box bottom at the front and back, sloping down to
/// a flat keel bottom around the middle. The keel stands for the knees, which sit under the belly
/// in the X stance: the belly cannot pass over obstacles taller than the keel clearance, while the
/// front and back of the trunk can pass over higher steps. Base frame, metres.

#include <Eigen/Core>

#include "rbcp/core/yaml_reader.h"
#include "rbcp/root_planner/convex_polytope.h"

namespace rbcp {

struct TrunkShapeConfig {
  Eigen::Vector3d box_min{-0.30, -0.165, -0.15};  ///< box corner, base frame [m]
  Eigen::Vector3d box_max{0.30, 0.165, 0.24};     ///< box corner, base frame [m]
  double keel_bottom_z = -0.325;                  ///< flat keel bottom height, base frame [m], <= box_min.z
  double keel_half_length = 0.05;                 ///< the keel bottom spans x in [-l, l] [m], within the box

  /// Reads box_min, box_max, keel_bottom_z, keel_half_length; strict.
  static TrunkShapeConfig Load(const YamlMap& map);
  /// The first inconsistency as "'key': expected X, got Y", or empty when valid.
  std::string Problem() const;
};

/// The convex trunk shape (box, plus the keel wedge when keel_bottom_z < box_min.z).
ConvexPolytope MakeTrunkShape(const TrunkShapeConfig& config);

}  // namespace rbcp
