#pragma once
/// Parameters of affordance extraction: which terrain surfaces the feet may push on.

#include <string>

#include "rbcp/core/yaml_reader.h"

namespace rbcp {

/// Support-surface parameters. The defaults are those of the reference ANYmal runs
/// (hpp-affordance 'Support' [0.5, 0.03, 0.00005]) with a true edge erosion of one foot radius
/// plus a centimetre.
struct AffordanceConfig {
  /// Steepest accepted surface: angle between the surface normal and world +z [deg], in (0, 90).
  double max_inclination_deg = 41.4;
  /// Largest angle between a triangle's normal and its region's seed-triangle normal [deg], in (0, 90).
  double neighbour_angle_deg = 9.9;
  /// Regions, and eroded surfaces, with this area or less are dropped [m^2], >= 0.
  double min_area = 0.5e-4;
  /// Every point of a surface is at least this far from its region's boundary [m], >= 0.
  double edge_margin = 0.04;

  /// Reads the four keys above from `map`; a missing, unknown or out-of-range key throws
  /// InputError naming the source and the key ("expected an angle in (0, 90) deg, got 95").
  static AffordanceConfig Load(const YamlMap& map);
  /// Load() on a YAML file whose top level holds exactly the keys above.
  static AffordanceConfig LoadFile(const std::string& path);

  /// The first out-of-range field as "'key': expected X, got Y", or an empty string when valid.
  std::string Problem() const;
};

}  // namespace rbcp
