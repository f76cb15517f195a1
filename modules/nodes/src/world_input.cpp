#include "rbcp/nodes/world_input.h"

#include <algorithm>
#include <utility>

#include "rbcp/core/error.h"
#include "rbcp/transport/convert.h"

namespace rbcp::nodes {

WorldInput::WorldInput(lcm::LCM& lcm, const std::string& terrain_channel, const std::string& affordances_channel)
    : terrain_msg_(lcm, terrain_channel), affordances_msg_(lcm, affordances_channel) {}

std::optional<std::string> WorldInput::Take(int64_t* latest_utime) {
  if (auto e = terrain_msg_.TakeDecodeError()) return e;
  if (auto e = affordances_msg_.TakeDecodeError()) return e;
  if (auto msg = terrain_msg_.Take()) {
    *latest_utime = std::max(*latest_utime, msg->utime);
    // A new terrain makes the surfaces of older terrains stale: they wait for their own.
    const auto new_terrain = [&] {
      terrain_since_ = msg->utime;
      changed_ = true;
      if (surfaces_ && surfaces_utime_ < terrain_since_) surfaces_.reset();
    };
    try {
      TriangleMesh mesh = transport::FromTerrainMsg(*msg);
      // The simulator republishes the same terrain for late processes: only new content counts.
      if (!terrain_ || mesh.vertices != terrain_->vertices || mesh.triangles != terrain_->triangles) {
        terrain_ = std::move(mesh);
        new_terrain();
      } else if (msg->utime < terrain_since_) {
        terrain_since_ = msg->utime;  // a restarted world counts its time from 0 again
      }
    } catch (const InputError& e) {
      terrain_.reset();
      new_terrain();
      return std::string(e.what());
    }
  }
  if (auto msg = affordances_msg_.Take()) {
    *latest_utime = std::max(*latest_utime, msg->utime);
    // Surfaces carry the utime of the terrain they were extracted from: older ones are stale.
    if (msg->utime < terrain_since_) return std::nullopt;
    surfaces_utime_ = msg->utime;
    try {
      std::vector<AffordanceSurface> surfaces = transport::FromAffordanceMsg(*msg);
      const auto same = [](const AffordanceSurface& a, const AffordanceSurface& b) {
        return a.vertices == b.vertices && a.normal == b.normal;
      };
      if (!surfaces_ || surfaces.size() != surfaces_->size() ||
          !std::equal(surfaces.begin(), surfaces.end(), surfaces_->begin(), same)) {
        surfaces_ = std::move(surfaces);
        changed_ = true;
      }
    } catch (const InputError& e) {
      surfaces_.reset();
      changed_ = true;
      return std::string(e.what());
    }
  }
  return std::nullopt;
}

bool WorldInput::TakeChanged() { return std::exchange(changed_, false); }

}  // namespace rbcp::nodes
