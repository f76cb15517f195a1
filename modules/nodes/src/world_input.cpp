#include "rbcp/nodes/world_input.h"

#include <algorithm>
#include <utility>

#include "rbcp/core/error.h"
#include "rbcp/transport/convert.h"

namespace rbcp::nodes {

WorldInput::WorldInput(lcm::LCM& lcm, const std::string& terrain_channel, const std::string& affordances_channel)
    : terrain_msg_(lcm, terrain_channel), affordances_msg_(lcm, affordances_channel) {}

std::optional<std::string> WorldInput::Take(transport::SimClock* clock) {
  if (auto e = terrain_msg_.TakeDecodeError()) return e;
  if (auto e = affordances_msg_.TakeDecodeError()) return e;
  if (auto msg = terrain_msg_.Take()) {
    if (std::string bad = clock->World(msg->utime, terrain_channel()); !bad.empty()) return bad;
    // A new terrain makes the surfaces of every other terrain stale, whatever their time (a
    // restarted world, or another operator's run, counts its time from 0 again): they wait for
    // their own.
    const auto new_terrain = [&] {
      terrain_utimes_.clear();
      changed_ = true;
      surfaces_.reset();
    };
    try {
      TriangleMesh mesh = transport::FromTerrainMsg(*msg);
      // The simulator republishes the same terrain for late processes: only new content counts.
      if (!terrain_ || mesh.vertices != terrain_->vertices || mesh.triangles != terrain_->triangles) {
        terrain_ = std::move(mesh);
        new_terrain();
      }
      RememberTerrainUtime(msg->utime);
    } catch (const InputError& e) {
      terrain_.reset();
      new_terrain();
      return std::string(e.what());
    }
  }
  if (auto msg = affordances_msg_.Take()) {
    if (std::string bad = clock->Input(msg->utime, affordances_channel()); !bad.empty()) return bad;
    // Surfaces carry the utime of the terrain message they were extracted from: those of a
    // message with other content are stale.
    if (std::find(terrain_utimes_.begin(), terrain_utimes_.end(), msg->utime) == terrain_utimes_.end()) {
      return std::nullopt;
    }
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

void WorldInput::RememberTerrainUtime(int64_t utime) {
  if (std::find(terrain_utimes_.begin(), terrain_utimes_.end(), utime) != terrain_utimes_.end()) return;
  terrain_utimes_.push_back(utime);
  if (terrain_utimes_.size() > kRememberedTerrainUtimes) terrain_utimes_.pop_front();
}

}  // namespace rbcp::nodes
