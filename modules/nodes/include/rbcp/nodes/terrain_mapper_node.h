#pragma once
/// The terrain mapper as a process (terrain_mapper): POINT_CLOUD (and ROBOT_STATE, CONTROLLER_STATUS for the time and the waits) in; the terrain
/// it knows out, as TERRAIN (a mesh of the known cells of its elevation map; unknown cells are no
/// terrain) beside ELEVATION_MAP (the grid, with each cell's variance), and STATUS.
///
/// Each cloud is placed in the world with the base pose it carries (the state estimate's at
/// capture) and the sensor's mount on the base, as the robot places its clouds, so the map is made
/// of the clouds alone, whichever other messages were lost on the way. No sensor looks under the
/// trunk: a new map starts with the plane through the feet of the reference stance under the
/// base pose of its first cloud (the robot starts standing). A cloud more than max_cloud_lead_s
/// ahead of the newest ROBOT_STATE is rejected with the reason on STATUS, as is a malformed one
/// (counts that disagree, a base or mount that is not a rigid pose, more points than the map
/// takes).
///
/// The map goes out when its clouds' time reaches the next multiple of publish_period_s, and when
/// the robot starts waiting at a step boundary (CONTROLLER_STATUS awaiting_since) with every cloud
/// heard before that status: that map's utime is the wait's, so a planner answering the wait knows
/// which map it is to plan on. Clouds and waits are handled in the order they were heard, however
/// many arrived between two Step() calls, so a run's log replayed one message at a time gives the
/// same maps. A cloud that never came (a gap in its sensor's seq: lost on the way) is counted as
/// missed on STATUS and ELEVATION_MAP. A map with no known cell is not sent. When the world's time
/// goes back (a new run), the map starts afresh.

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <variant>

#include "rbcp/mapping/terrain_map.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/elevation_map_t.hpp"
#include "rbcp_msgs/point_cloud_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::nodes {

struct TerrainMapperNodeChannels {
  std::string point_cloud = channels::kPointCloud;
  std::string robot_state = channels::kRobotState;
  std::string controller_status = channels::kControllerStatus;
  std::string terrain = channels::kTerrain;
  std::string elevation_map = channels::kElevationMap;
  std::string status = channels::kStatus;
};

/// The process's limits on its inputs (not map parameters: those are mapping::MapperConfig's).
struct TerrainMapperNodeOptions {
  double max_cloud_lead_s = 0.5;   ///< [s, simulated] a cloud this far ahead of the newest state is rejected
  double footprint_variance_m2 = 4e-4;  ///< the terrain under the trunk at a map's start (TerrainMap::InitializeFootprint) [m^2]
  double footprint_margin_m = 0.15;     ///< ... and around the feet, this far [m]
  /// Clouds heard and not yet fused; the oldest goes beyond. The simulator, 9 times faster than
  /// real time, sends two sensors' 10 Hz clouds at about 180 a second of wall time, a few tens
  /// during one of the mapper's steps on a loaded machine (16 were exceeded a few times a run); at
  /// most about 10 MB of clouds (128 of 3072 points) wait.
  std::size_t max_pending_clouds = 128;
};

/// Why a cloud was not integrated (for STATUS and tests).
std::optional<std::string> CheckCloud(const rbcp_msgs::point_cloud_t& msg, int max_points);

/// The ELEVATION_MAP message of `grid` (its known cells; NaN elsewhere).
rbcp_msgs::elevation_map_t ToElevationMapMsg(const mapping::ElevationMap& grid, int64_t utime, int64_t terrain_id,
                                             int64_t clouds_fused, int64_t clouds_missed);
/// The grid an ELEVATION_MAP message carries, as an ElevationMap (for judging it against the
/// true terrain). Throws InputError when its counts disagree, its resolution is not positive,
/// the grid is not square or its origin is not on a multiple of the resolution.
mapping::ElevationMap FromElevationMapMsg(const rbcp_msgs::elevation_map_t& msg);

class TerrainMapperNode {
 public:
  static constexpr const char* kProcessName = "terrain_mapper";

  /// `robot` must outlive the node.
  TerrainMapperNode(lcm::LCM& lcm, const mapping::MapperConfig& config, const RobotModel& robot,
                    TerrainMapperNodeOptions options = {}, TerrainMapperNodeChannels channels = {});

  /// Handles the clouds and waits heard since the last call, in the order heard: integrates the
  /// clouds (rejecting what cannot be placed) and publishes the map when due. Returns true if
  /// anything was handled.
  bool Step();
  /// Republishes STATUS, and the latest TERRAIN unchanged (for a process that started after it
  /// went out: while the robot waits, the world stands still and no new map comes).
  void Heartbeat();

  const mapping::TerrainMap& map() const { return map_; }
  int64_t clouds_fused() const { return clouds_fused_; }
  int64_t clouds_rejected() const { return clouds_rejected_; }
  /// Clouds that never came: gaps in a sensor's seq, over this map.
  int64_t clouds_missed() const { return clouds_missed_; }
  int64_t maps_published() const { return maps_published_; }
  transport::StatusReporter& status() { return status_; }

 private:
  void TakeState(const rbcp_msgs::robot_state_t& msg);
  void TakeCloud(const rbcp_msgs::point_cloud_t& msg);
  void TakeControllerStatus(const rbcp_msgs::controller_status_t& msg);
  void Reject(const rbcp_msgs::point_cloud_t& msg, const std::string& why);
  /// Fuses `msg` unless it is from the future.
  void IntegrateIfPlaced(const rbcp_msgs::point_cloud_t& msg);
  void Integrate(const rbcp_msgs::point_cloud_t& msg);
  /// Counts the clouds of `msg`'s sensor that never came before it.
  void CountMissed(const rbcp_msgs::point_cloud_t& msg);
  /// The map of the wait that began at `wait` (every cloud heard before it is in).
  void PublishWait(int64_t wait);
  void Publish(int64_t utime, double compute_ms);
  void Restart();

  mapping::MapperConfig config_;
  const RobotModel& robot_;
  TerrainMapperNodeOptions options_;
  TerrainMapperNodeChannels channels_;
  lcm::LCM& lcm_;
  transport::MessagePublisher publisher_;
  transport::StatusReporter status_;
  mapping::TerrainMap map_;
  std::optional<rbcp_msgs::terrain_mesh_t> last_terrain_;  ///< the latest map sent
  int64_t newest_state_utime_ = -1;                 ///< of the ROBOT_STATE messages heard
  /// What Step() has to handle, in the order heard: a cloud, or the start of a wait (its utime).
  using Input = std::variant<rbcp_msgs::point_cloud_t, int64_t>;
  std::deque<Input> pending_;
  std::size_t pending_clouds_ = 0;    ///< clouds in pending_
  int64_t last_wait_heard_ = -1;      ///< awaiting_since of the newest wait heard
  std::map<std::string, int64_t> last_seq_;  ///< per sensor, the seq of its newest cloud heard
  int64_t newest_cloud_utime_ = -1;  ///< of the clouds integrated
  int64_t published_utime_ = -1;     ///< of the last map sent
  int64_t next_publish_utime_ = 0;
  int64_t clouds_fused_ = 0;
  int64_t clouds_rejected_ = 0;
  int64_t clouds_missed_ = 0;
  int64_t maps_published_ = 0;
  double integrate_ms_ = 0.0;  ///< wall time integrating since the last map
  bool dirty_ = false;         ///< clouds integrated since the last map
  bool footprint_done_ = false;  ///< this map started with the terrain under the trunk
  transport::EveryMessage<rbcp_msgs::robot_state_t> state_in_;
  transport::EveryMessage<rbcp_msgs::point_cloud_t> cloud_in_;
  transport::EveryMessage<rbcp_msgs::controller_status_t> controller_in_;
};

}  // namespace rbcp::nodes
