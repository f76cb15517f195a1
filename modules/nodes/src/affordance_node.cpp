#include "rbcp/nodes/affordance_node.h"

#include <chrono>

#include "rbcp/core/error.h"
#include "rbcp/transport/convert.h"

namespace rbcp::nodes {

AffordanceNode::AffordanceNode(lcm::LCM& lcm, const AffordanceConfig& config, AffordanceNodeChannels channels)
    : channels_(std::move(channels)),
      publisher_(lcm),
      extractor_(config),
      terrain_(lcm, channels_.terrain),
      status_(lcm, kProcessName, channels_.status) {}

bool AffordanceNode::Step() {
  if (auto error = terrain_.TakeDecodeError()) {
    status_.Failed(latest_utime_, latest_utime_, 0.0, *error);
    return true;
  }
  auto msg = terrain_.Take();
  if (!msg) return false;
  latest_utime_ = msg->utime;
  status_.Busy(msg->utime, msg->utime);
  const auto start = std::chrono::steady_clock::now();
  try {
    const TriangleMesh mesh = transport::FromTerrainMsg(*msg);
    // The simulator republishes its terrain for late processes: the same terrain's surfaces
    // are sent again, not extracted again.
    if (msg->terrain_id != surfaces_terrain_id_) {
      surfaces_terrain_id_ = 0;
      surfaces_ = extractor_.Extract(mesh);
      surfaces_terrain_id_ = msg->terrain_id;
    }
  } catch (const InputError& e) {
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    surfaces_.clear();
    surfaces_terrain_id_ = 0;
    status_.Failed(msg->utime, msg->utime, ms, e.what());
    return true;
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const auto out = transport::ToAffordanceMsg(surfaces_, msg->utime, msg->terrain_id);
  const std::string problem = publisher_.Publish(channels_.affordances, out);
  if (!problem.empty()) {
    status_.Failed(msg->utime, msg->utime, ms, problem);
    return true;
  }
  status_.Ok(msg->utime, msg->utime, ms);
  return true;
}

void AffordanceNode::Heartbeat() { status_.Heartbeat(latest_utime_); }

}  // namespace rbcp::nodes
