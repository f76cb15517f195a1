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
    changed_ = true;
    try {
      terrain_ = transport::FromTerrainMsg(*msg);
    } catch (const InputError& e) {
      terrain_.reset();
      return std::string(e.what());
    }
  }
  if (auto msg = affordances_msg_.Take()) {
    *latest_utime = std::max(*latest_utime, msg->utime);
    changed_ = true;
    try {
      surfaces_ = transport::FromAffordanceMsg(*msg);
    } catch (const InputError& e) {
      surfaces_.reset();
      return std::string(e.what());
    }
  }
  return std::nullopt;
}

bool WorldInput::TakeChanged() { return std::exchange(changed_, false); }

}  // namespace rbcp::nodes
