#include "rbcp/nodes/world_input.h"

#include <algorithm>
#include <utility>

#include "rbcp/core/error.h"
#include "rbcp/transport/convert.h"

namespace rbcp::nodes {

WorldInput::WorldInput(lcm::LCM& lcm, const std::string& terrain_channel, const std::string& affordances_channel)
    : terrain_msg_(lcm, terrain_channel), affordances_msg_(lcm, affordances_channel) {}

std::optional<RejectedInput> WorldInput::Take(transport::SimClock* clock) {
  if (auto e = terrain_msg_.TakeDecodeError()) return RejectedInput::Undecodable(std::move(*e));
  if (auto e = affordances_msg_.TakeDecodeError()) return RejectedInput::Undecodable(std::move(*e));
  if (auto msg = terrain_msg_.Take()) {
    if (auto bad = clock->World(msg->utime, terrain_channel())) return RejectedInput::Time(std::move(*bad));
    // A new terrain makes the surfaces of every other terrain stale: they wait for their own.
    try {
      TriangleMesh mesh = transport::FromTerrainMsg(*msg);
      // The simulator republishes the same terrain for late processes: only new content counts.
      if (!terrain_ || msg->terrain_id != terrain_id_) {
        terrain_ = std::move(mesh);
        terrain_id_ = msg->terrain_id;
        terrain_utime_ = msg->utime;
        changed_ = true;
        surfaces_.reset();
      } else {
        terrain_utime_ = std::max(terrain_utime_, msg->utime);
      }
    } catch (const InputError& e) {
      terrain_.reset();
      changed_ = true;
      surfaces_.reset();
      return RejectedInput::Content(e.what());
    }
  }
  if (auto msg = affordances_msg_.Take()) {
    if (auto bad = clock->Input(msg->utime, affordances_channel())) return RejectedInput::Time(std::move(*bad));
    // Surfaces of another terrain than the current one are stale (or early: the terrain they
    // come from is still on its way, and they come again after it).
    if (!terrain_ || msg->terrain_id != terrain_id_) return std::nullopt;
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
      return RejectedInput::Content(e.what());
    }
  }
  return std::nullopt;
}

bool WorldInput::TakeChanged() { return std::exchange(changed_, false); }

}  // namespace rbcp::nodes
