#pragma once
/// The world of a planner process: the latest TERRAIN mesh and AFFORDANCES contact surfaces,
/// decoded and validated, with a flag raised whenever either changes.

#include <lcm/lcm-cpp.hpp>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/sim_clock.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::nodes {

class WorldInput {
 public:
  WorldInput(lcm::LCM& lcm, const std::string& terrain_channel, const std::string& affordances_channel);

  /// Takes the messages received since the last call; TERRAIN sets the clock, AFFORDANCES move it
  /// (a message with a time the clock rejects is rejected).
  /// Returns why one was rejected (undecodable, or an invalid mesh or surface); that part of
  /// the world is then unknown until a valid message arrives. Surfaces belong to the terrain
  /// message whose utime they carry: a terrain of new content drops the current surfaces, and
  /// only surfaces carrying the utime of a message of the current terrain are taken, so a
  /// terrain and the surfaces of another never pair, even when a restarted world counts its
  /// time from 0 again.
  std::optional<std::string> Take(transport::SimClock* clock);

  const std::optional<TriangleMesh>& terrain() const { return terrain_; }
  const std::optional<std::vector<AffordanceSurface>>& surfaces() const { return surfaces_; }
  bool Ready() const { return terrain_.has_value() && surfaces_.has_value(); }
  /// True once after the terrain or the surfaces changed (the call clears it): a message that
  /// repeats the current content is no change.
  bool TakeChanged();

  const std::string& terrain_channel() const { return terrain_msg_.channel(); }
  const std::string& affordances_channel() const { return affordances_msg_.channel(); }

 private:
  transport::LatestMessage<rbcp_msgs::terrain_mesh_t> terrain_msg_;
  transport::LatestMessage<rbcp_msgs::affordance_set_t> affordances_msg_;
  std::optional<TriangleMesh> terrain_;
  std::optional<std::vector<AffordanceSurface>> surfaces_;
  void RememberTerrainUtime(int64_t utime);

  /// The utimes of the latest messages of the current terrain (it is republished every period).
  static constexpr std::size_t kRememberedTerrainUtimes = 256;
  bool changed_ = false;
  std::deque<int64_t> terrain_utimes_;
};

}  // namespace rbcp::nodes
