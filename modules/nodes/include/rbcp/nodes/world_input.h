#pragma once
/// The world of a planner process: the latest TERRAIN mesh and AFFORDANCES contact surfaces,
/// decoded and validated, with a flag raised whenever either changes.

#include <lcm/lcm-cpp.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/nodes/rejected_input.h"
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
  /// whose terrain_id they carry: a terrain of new content drops the current surfaces, and only
  /// surfaces of the current terrain are taken, so a terrain and the surfaces of another never
  /// pair, whatever the messages' times.
  std::optional<RejectedInput> Take(transport::SimClock* clock);

  const std::optional<TriangleMesh>& terrain() const { return terrain_; }
  /// The current terrain's transport::TerrainId; 0 while there is none.
  int64_t terrain_id() const { return terrain_ ? terrain_id_ : 0; }
  /// The utime of the newest TERRAIN message with the current terrain's content (a map sent
  /// again, unchanged, for a later time moves it on); -1 while there is none.
  int64_t terrain_utime() const { return terrain_ ? terrain_utime_ : -1; }
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
  int64_t terrain_id_ = 0;
  int64_t terrain_utime_ = -1;
  bool changed_ = false;
};

}  // namespace rbcp::nodes
