#pragma once
/// Node tests: publishes a scenario's world as the simulator and affordance_extractor would.

#include <lcm/lcm-cpp.hpp>

#include <string>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"

namespace rbcp::nodes::test {

/// TERRAIN and AFFORDANCES (extracted with config_dir/affordance.yaml) of `scenario`, at `utime`.
inline void PublishWorld(lcm::LCM& lcm, const Scenario& scenario, const std::string& config_dir, int64_t utime = 100) {
  const auto surfaces = AffordanceExtractor(AffordanceConfig::Load(YamlMap::LoadFile(config_dir + "/affordance.yaml")))
                            .Extract(scenario.terrain_mesh);
  const auto terrain = transport::ToTerrainMsg(scenario.terrain_mesh, utime, scenario.name);
  const auto affordances = transport::ToAffordanceMsg(surfaces, utime, terrain.terrain_id);
  lcm.publish(channels::kTerrain, &terrain);
  lcm.publish(channels::kAffordances, &affordances);
}

}  // namespace rbcp::nodes::test
