#pragma once
// The recorded affordance log (tests/data/affordances_darpa_rubble.lcmlog, made by
// tests/data/record_affordance_log.sh from a real run) and comparisons of surface sets.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rbcp/transport/channels.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"
#include "support/lcm_log.h"

namespace rbcp::testing {

inline std::string AffordanceLogPath() { return std::string(RBCP_SOURCE_DIR) + "/tests/data/affordances_darpa_rubble.lcmlog"; }

// The first AFFORDANCES event of the log and the TERRAIN event it answers (same utime).
struct RecordedPair {
  RecordedEvent terrain;
  rbcp_msgs::affordance_set_t affordances;
};

inline RecordedPair FindPair(const std::vector<RecordedEvent>& events) {
  std::vector<std::pair<int64_t, const RecordedEvent*>> terrains;
  for (const auto& e : events) {
    if (e.channel == channels::kTerrain) {
      rbcp_msgs::terrain_mesh_t terrain;
      EXPECT_TRUE(e.DecodeInto(terrain));
      terrains.emplace_back(terrain.utime, &e);
    } else if (e.channel == channels::kAffordances) {
      rbcp_msgs::affordance_set_t a;
      EXPECT_TRUE(e.DecodeInto(a));
      for (const auto& [utime, terrain] : terrains) {
        if (utime == a.utime) return {*terrain, a};
      }
    }
  }
  return {};
}

inline void ExpectSameSurfaces(const rbcp_msgs::affordance_set_t& got, const rbcp_msgs::affordance_set_t& want) {
  ASSERT_EQ(got.num_surfaces, want.num_surfaces);
  for (int i = 0; i < want.num_surfaces; ++i) {
    const auto& g = got.surfaces[static_cast<std::size_t>(i)];
    const auto& w = want.surfaces[static_cast<std::size_t>(i)];
    ASSERT_EQ(g.num_vertices, w.num_vertices) << "surface " << i;
    EXPECT_NEAR(g.area, w.area, 1e-9) << "surface " << i;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(g.normal[k], w.normal[k], 1e-9) << "surface " << i;
    for (int v = 0; v < w.num_vertices; ++v) {
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(g.vertices[static_cast<std::size_t>(v)][static_cast<std::size_t>(k)],
                    w.vertices[static_cast<std::size_t>(v)][static_cast<std::size_t>(k)], 1e-9)
            << "surface " << i << " vertex " << v;
      }
    }
  }
}

}  // namespace rbcp::testing
