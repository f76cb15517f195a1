#pragma once
/// The trunk's collision shape for root planning: a box with a keel under the belly.
///
/// Seen from the side, the bottom is a "V": the box bottom at the front and back, sloping down to
/// a flat keel bottom around the middle. The keel stands for the knees, which sit under the belly
/// in the X stance: the belly cannot pass over obstacles taller than the keel clearance, while the
/// front and back of the trunk can pass over higher steps. Base frame, metres.

#include <Eigen/Core>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/root_planner/convex_polytope.h"

namespace rbcp {

struct TrunkShapeConfig {
  Eigen::Vector3d box_min{-0.30, -0.28, -0.15};
  Eigen::Vector3d box_max{0.30, 0.28, 0.24};
  double keel_bottom_z = -0.325;
  double keel_half_length = 0.05;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("box_min", &box_min, "m", bounds::Any(), "the box's lowest corner, base frame");
    v->Visit("box_max", &box_max, "m", bounds::Any(), "the box's highest corner, base frame");
    v->Rule("box_max", (box_max - box_min).minCoeff() > 0.0, "every coordinate above box_min's",
            "(" + ConfigNumber(box_max.x()) + ", " + ConfigNumber(box_max.y()) + ", " + ConfigNumber(box_max.z()) + ")");
    v->Visit("keel_bottom_z", &keel_bottom_z, "m", bounds::Any().AtMost(box_min.z(), "box_min z"),
             "height of the keel's flat bottom, base frame");
    v->Visit("keel_half_length", &keel_half_length, "m",
             bounds::Positive().Below(0.5 * (box_max.x() - box_min.x()), "half the box length"),
             "the keel's flat bottom spans x in [-keel_half_length, keel_half_length], sloping up to the box "
             "bottom at the front and back");
  }

  /// Reads box_min, box_max, keel_bottom_z, keel_half_length; strict.
  static TrunkShapeConfig Load(const YamlMap& map) { return LoadConfig<TrunkShapeConfig>(map); }
  /// Throws InputError naming `where` and the first inconsistency.
  void Validate(const std::string& where = "TrunkShapeConfig") const { ValidateConfig(*this, where); }
};

/// The convex trunk shape (box, plus the keel wedge when keel_bottom_z < box_min.z).
ConvexPolytope MakeTrunkShape(const TrunkShapeConfig& config);

}  // namespace rbcp
