#pragma once
/// One-shot affordance extraction on a scenario file, for `affordance_extractor --once`.

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

#include "rbcp/affordance/affordance_extractor.h"

namespace rbcp::nodes {

struct AffordanceReport {
  std::string scenario;
  std::size_t triangles = 0;
  std::vector<AffordanceSurface> surfaces;
  double extract_ms = 0.0;  ///< wall time of the extraction [ms]
};

/// Loads the scenario (throws rbcp::InputError on a bad file) and extracts its surfaces.
AffordanceReport ExtractScenario(const std::string& scenario_path, const AffordanceConfig& config);

/// {"scenario", "triangles", "surfaces": [{"vertices", "normal", "area"}], "extract_ms"}
nlohmann::json ToJson(const AffordanceReport& report);

/// A few human-readable lines: surface count, total area, timing.
std::string Summary(const AffordanceReport& report);

}  // namespace rbcp::nodes
