#pragma once
/// Parameters of the static-equilibrium tests (config/equilibrium.yaml). Contacts are points with
/// linearised friction cones; gravity is kGravity (static_equilibrium.h) along world -z.

#include <string>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/yaml_reader.h"

namespace rbcp {

struct EquilibriumConfig {
  double friction = 0.5;
  int generators_per_contact = 4;
  double robustness_threshold_N = 2.0;
  double normal_force_slack = 0.01;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("friction", &friction, "", bounds::Positive(), "Coulomb friction coefficient mu of every contact");
    v->Visit("generators_per_contact", &generators_per_contact, "", bounds::Closed(3, 64),
             "edges of the pyramid inscribed in each friction cone; one edge points up the slope of the surface");
    v->Visit("robustness_threshold_N", &robustness_threshold_N, "N", bounds::NonNegative(),
             "a stance is stable when every contact force can absorb a force error this large without leaving its "
             "cone (see EquilibriumResult)");
    v->Visit("normal_force_slack", &normal_force_slack, "", bounds::Closed(0, 1),
             "force distribution: the largest normal force may exceed its least achievable value by this fraction, "
             "to leave room for a larger friction margin (0 keeps the exact minimum)");
  }

  /// Reads every key strictly (missing or unknown keys, wrong types and out-of-range values throw
  /// InputError naming the key).
  static EquilibriumConfig Load(const YamlMap& map) { return LoadConfig<EquilibriumConfig>(map); }
  static EquilibriumConfig LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
  /// Throws InputError describing the first out-of-range value.
  void Validate(const std::string& where = "EquilibriumConfig") const { ValidateConfig(*this, where); }
};

}  // namespace rbcp
