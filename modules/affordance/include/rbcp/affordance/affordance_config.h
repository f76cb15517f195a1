#pragma once
/// Parameters of affordance extraction (config/affordance.yaml): which parts of the terrain the
/// feet may push on. Every key is required and no other key is accepted.

#include <string>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/yaml_reader.h"

namespace rbcp {

/// Support surfaces: planar regions of the terrain, eroded from their boundary.
struct AffordanceConfig {
  double max_inclination_deg = 41.4;
  double neighbour_angle_deg = 9.9;
  double min_area = 0.5e-4;
  double edge_margin = 0.04;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("max_inclination_deg", &max_inclination_deg, "deg", bounds::Open(0, 90),
             "steepest support surface: angle between its normal and world +z");
    v->Visit("neighbour_angle_deg", &neighbour_angle_deg, "deg", bounds::Open(0, 90),
             "a triangle joins a region if its normal is within this angle of the region's seed-triangle normal");
    v->Visit("min_area", &min_area, "m^2", bounds::NonNegative(),
             "regions and eroded surfaces of this area or less are dropped");
    v->Visit("edge_margin", &edge_margin, "m", bounds::NonNegative(),
             "every surface point is at least this far from its region's boundary (a foot sphere on it stays on "
             "the terrain)");
  }

  /// Reads the keys above from `map`; a missing, unknown or out-of-range key throws InputError
  /// naming the source and the key ("expected a number in (0, 90) [deg], got 95").
  static AffordanceConfig Load(const YamlMap& map) { return LoadConfig<AffordanceConfig>(map); }
  /// Load() on a YAML file whose top level holds exactly the keys above.
  static AffordanceConfig LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
  /// Throws InputError naming `where` and the first out-of-range key.
  void Validate(const std::string& where = "AffordanceConfig") const { ValidateConfig(*this, where); }
};

}  // namespace rbcp
