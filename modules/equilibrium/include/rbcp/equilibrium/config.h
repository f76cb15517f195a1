#pragma once
/// Parameters of the static-equilibrium tests (config/equilibrium.yaml).

#include <string>

#include "rbcp/core/yaml_reader.h"

namespace rbcp {

struct EquilibriumConfig {
  /// Coulomb friction coefficient mu [-] of every contact.
  double friction = 0.5;
  /// Edges of the pyramid inscribed in each friction cone [-], at least 3.
  int generators_per_contact = 4;
  /// Minimum robustness [N] for a stance to count as statically stable (see EquilibriumResult).
  /// The reference runs used 3 (flat), 5 (slalom debris), 2 (plinth) and 0 (DARPA).
  double robustness_threshold_N = 2.0;
  /// Force distribution: relative slack [-] on the smallest achievable maximum normal force
  /// within which the friction margin is then maximised (0 keeps the exact minimum).
  double normal_force_slack = 0.01;

  /// Reads every key strictly (missing or unknown keys, wrong types and out-of-range values throw
  /// InputError naming the key).
  static EquilibriumConfig Load(const YamlMap& map);
  static EquilibriumConfig LoadFile(const std::string& path);

  /// Throws InputError describing the first out-of-range value.
  void Validate(const std::string& where = "EquilibriumConfig") const;
};

}  // namespace rbcp
