#pragma once
/// The affordance extraction process: TERRAIN in (whole or in parts), AFFORDANCES (in parts when
/// large) and STATUS out.

#include <lcm/lcm-cpp.hpp>

#include <string>
#include <vector>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::nodes {

struct AffordanceNodeChannels {
  std::string terrain = channels::kTerrain;
  std::string affordances = channels::kAffordances;
  std::string status = channels::kStatus;
};

class AffordanceNode {
 public:
  static constexpr const char* kProcessName = "affordance_extractor";

  AffordanceNode(lcm::LCM& lcm, const AffordanceConfig& config, AffordanceNodeChannels channels = {});

  /// Handles the newest terrain received since the last call (older ones are superseded):
  /// extracts the surfaces and publishes them, or publishes FAILED with the reason when the
  /// terrain is malformed. Returns true if a terrain (or a malformed message) was handled.
  bool Step();
  /// Republishes the current status, so lcm-spy and the launcher see the process is up.
  void Heartbeat();

  const std::vector<AffordanceSurface>& surfaces() const { return surfaces_; }
  transport::StatusReporter& status() { return status_; }

 private:
  AffordanceNodeChannels channels_;
  transport::MessagePublisher publisher_;
  AffordanceExtractor extractor_;
  transport::LatestMessage<rbcp_msgs::terrain_mesh_t> terrain_;
  transport::StatusReporter status_;
  std::vector<AffordanceSurface> surfaces_;
  int64_t surfaces_terrain_id_ = 0;  ///< the terrain surfaces_ were extracted from; 0: none
  int64_t latest_utime_ = 0;
};

}  // namespace rbcp::nodes
