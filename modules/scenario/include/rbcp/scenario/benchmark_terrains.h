#pragma once
/// The four benchmark terrains of Geisert et al. 2019 (flat ground, slalom debris, plinth, DARPA
/// rubble), rebuilt from boxes after the measured geometry of the HPP environment meshes.
/// config/scenarios/<name>.yaml are generated from here by the generate_scenarios program.

#include <string>
#include <vector>

#include "rbcp/scenario/scenario.h"

namespace rbcp {

struct BenchmarkScenario {
  Scenario scenario;        ///< boxes only; path empty
  std::string description;  ///< one line, written as a comment into the file
};

/// flat_ground, slalom_debris, plinth, darpa_rubble, in this order.
std::vector<BenchmarkScenario> MakeBenchmarkScenarios();

/// The exact file content for config/scenarios/<name>.yaml: a "generated" comment, the
/// description, then ScenarioToYaml. Checks (always) that the text loads back and that no upward
/// face of the terrain is covered by another box.
std::string BenchmarkScenarioText(const BenchmarkScenario& benchmark);

}  // namespace rbcp
