#include "rbcp/nodes/terrain_mapper_node.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <limits>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/sim_clock.h"

namespace rbcp::nodes {
namespace {

double Seconds(int64_t utime) { return static_cast<double>(utime) * 1e-6; }

/// Why a (w, x, y, z) orientation [4] of a message is no rotation: not a unit quaternion.
std::optional<std::string> NotAUnitQuaternion(const double* q) {
  const double norm = Eigen::Vector4d(q[0], q[1], q[2], q[3]).norm();
  if (std::abs(norm - 1.0) <= transport::kUnitTolerance) return std::nullopt;
  return "is not a unit quaternion (norm " + FixedNumber(norm, 4) + ")";
}

/// The rigid pose of a position [3] and a (w, x, y, z) orientation [4], as the messages carry them.
Eigen::Isometry3d PoseOf(const double* position, const double* orientation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond(orientation[0], orientation[1], orientation[2], orientation[3])
                      .normalized()
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(position[0], position[1], position[2]);
  return pose;
}

}  // namespace

std::optional<std::string> CheckCloud(const rbcp_msgs::point_cloud_t& msg, int max_points) {
  const std::string what = "POINT_CLOUD '" + msg.sensor + "' " + std::to_string(msg.seq) + ": ";
  if (msg.num_points < 0 || static_cast<std::size_t>(msg.num_points) != msg.points.size()) {
    return what + "num_points " + std::to_string(msg.num_points) + " but " + std::to_string(msg.points.size()) + " points";
  }
  if (msg.num_points > max_points) {
    return what + std::to_string(msg.num_points) + " points, more than the map takes in one cloud (" +
           std::to_string(max_points) + ", mapper.yaml max_points_per_cloud)";
  }
  if (!transport::AllFinite(msg.base_position, 3) || !transport::AllFinite(msg.base_orientation, 4)) {
    return what + "the base pose is not finite";
  }
  if (!transport::AllFinite(msg.mount_position, 3) || !transport::AllFinite(msg.mount_orientation, 4)) {
    return what + "the sensor's mount is not finite";
  }
  if (std::abs(msg.base_position[0]) > transport::kMaxCoordinate_m || std::abs(msg.base_position[1]) > transport::kMaxCoordinate_m ||
      std::abs(msg.base_position[2]) > transport::kMaxCoordinate_m) {
    return what + "the base is beyond " + FixedNumber(transport::kMaxCoordinate_m, 0) + " m";
  }
  if (auto bad = NotAUnitQuaternion(msg.base_orientation)) return what + "the base orientation " + *bad;
  if (std::abs(msg.mount_position[0]) > 10.0 || std::abs(msg.mount_position[1]) > 10.0 ||
      std::abs(msg.mount_position[2]) > 10.0) {
    return what + "the sensor's mount is more than 10 m from the base";
  }
  if (auto bad = NotAUnitQuaternion(msg.mount_orientation)) return what + "the sensor's mount orientation " + *bad;
  if (!std::isfinite(msg.range_noise_std) || msg.range_noise_std < 0.0f || msg.range_noise_std > 1.0f) {
    return what + "range_noise_std expected in [0, 1] m, got " + FixedNumber(msg.range_noise_std, 4);
  }
  if (msg.utime < 0) return what + "negative utime " + std::to_string(msg.utime);
  return std::nullopt;
}

rbcp_msgs::elevation_map_t ToElevationMapMsg(const mapping::ElevationMap& grid, int64_t utime, int64_t terrain_id,
                                             int64_t clouds_fused, int64_t clouds_missed) {
  rbcp_msgs::elevation_map_t em;
  em.utime = utime;
  em.terrain_id = terrain_id;
  em.clouds_fused = clouds_fused;
  em.clouds_missed = clouds_missed;
  em.origin[0] = grid.origin().x();
  em.origin[1] = grid.origin().y();
  em.resolution = grid.resolution();
  em.num_x = grid.num_x();
  em.num_y = grid.num_y();
  em.num_cells = em.num_x * em.num_y;
  em.height.assign(static_cast<std::size_t>(em.num_cells), std::numeric_limits<float>::quiet_NaN());
  em.variance = em.height;
  for (int iy = 0; iy < em.num_y; ++iy) {
    for (int ix = 0; ix < em.num_x; ++ix) {
      if (const auto cell = grid.At(ix, iy)) {
        const auto i = static_cast<std::size_t>(iy * em.num_x + ix);
        em.height[i] = static_cast<float>(cell->height);
        em.variance[i] = static_cast<float>(cell->variance);
      }
    }
  }
  return em;
}

mapping::ElevationMap FromElevationMapMsg(const rbcp_msgs::elevation_map_t& msg) {
  const double r = msg.resolution;
  if (!(r > 0.0) || !std::isfinite(r)) throw InputError("ELEVATION_MAP: resolution expected > 0, got " + FixedNumber(r, 4));
  if (msg.num_x <= 0 || msg.num_x != msg.num_y) throw InputError("ELEVATION_MAP: expected a square grid");
  if (msg.num_cells != msg.num_x * msg.num_y || msg.height.size() != static_cast<std::size_t>(msg.num_cells) ||
      msg.variance.size() != msg.height.size()) {
    throw InputError("ELEVATION_MAP: the cell count disagrees with the grid");
  }
  const Eigen::Vector2d origin(msg.origin[0], msg.origin[1]);
  const Eigen::Vector2d in_cells = origin / r;
  if (!origin.allFinite() || (in_cells - in_cells.array().round().matrix()).norm() > 1e-6) {
    throw InputError("ELEVATION_MAP: the origin is not on a multiple of the resolution");
  }
  mapping::ElevationMapConfig config;
  config.resolution_m = r;
  config.window_m = r * msg.num_x;
  config.recenter_distance_m = 0.25 * config.window_m;
  mapping::ElevationMap grid(config);
  // The window centred where the message's is: the same cells.
  grid.Recenter(origin + Eigen::Vector2d::Constant((msg.num_x / 2 + 0.5) * r));
  for (int iy = 0; iy < msg.num_y; ++iy) {
    for (int ix = 0; ix < msg.num_x; ++ix) {
      const auto i = static_cast<std::size_t>(iy * msg.num_x + ix);
      if (std::isfinite(msg.height[i]) && std::isfinite(msg.variance[i]) && msg.variance[i] > 0.0f) {
        grid.FuseCell(ix, iy, msg.height[i], msg.variance[i], 0.0, /*gate=*/false);
      }
    }
  }
  return grid;
}

TerrainMapperNode::TerrainMapperNode(lcm::LCM& lcm, const mapping::MapperConfig& config, const RobotModel& robot,
                                     TerrainMapperNodeOptions options, TerrainMapperNodeChannels channels)
    : config_(config),
      robot_(robot),
      options_(options),
      channels_(std::move(channels)),
      lcm_(lcm),
      publisher_(lcm),
      status_(lcm, kProcessName, channels_.status),
      map_(config),
      state_in_(
          lcm, channels_.robot_state, [this](const rbcp_msgs::robot_state_t& m) { TakeState(m); },
          [this](const std::string& why) { status_.Failed(newest_cloud_utime_, 0, 0.0, why); }),
      cloud_in_(
          lcm, channels_.point_cloud, [this](const rbcp_msgs::point_cloud_t& m) { TakeCloud(m); },
          [this](const std::string& why) {
            clouds_rejected_ += 1;
            status_.Failed(newest_cloud_utime_, 0, 0.0, why);
          }),
      controller_in_(
          lcm, channels_.controller_status,
          [this](const rbcp_msgs::controller_status_t& m) { TakeControllerStatus(m); },
          [this](const std::string& why) { status_.Failed(std::max<int64_t>(newest_cloud_utime_, 0), 0, 0.0, why); }) {
  config_.Validate();
}

void TerrainMapperNode::Restart() {
  map_ = mapping::TerrainMap(config_);
  newest_state_utime_ = -1;
  pending_.clear();
  pending_clouds_ = 0;
  last_wait_heard_ = -1;
  last_seq_.clear();
  clouds_missed_ = 0;
  newest_cloud_utime_ = published_utime_ = -1;
  next_publish_utime_ = 0;
  dirty_ = false;
  footprint_done_ = false;
}

void TerrainMapperNode::TakeState(const rbcp_msgs::robot_state_t& msg) {
  if (msg.utime < 0 || msg.utime > transport::SimClock::kMaxUtime) {
    status_.Failed(std::max<int64_t>(newest_cloud_utime_, 0), msg.utime, 0.0,
                   "ROBOT_STATE: utime " + std::to_string(msg.utime) + " us is not a simulated time");
    return;
  }
  if (newest_state_utime_ >= 0 && msg.utime + 1'000'000 < newest_state_utime_) {
    // The world's time went back by more than a second: a new run, a new map.
    if (status_.verbose()) {
      std::fprintf(stderr, "[%s] the world's time went back to %.3f s: a new map\n", kProcessName, Seconds(msg.utime));
    }
    Restart();
  }
  newest_state_utime_ = std::max(newest_state_utime_, msg.utime);
}

void TerrainMapperNode::TakeCloud(const rbcp_msgs::point_cloud_t& msg) {
  if (auto why = CheckCloud(msg, config_.max_points_per_cloud)) {
    Reject(msg, *why);
    return;
  }
  CountMissed(msg);
  pending_.emplace_back(msg);
  if (++pending_clouds_ > options_.max_pending_clouds) {
    // A flood between two steps: the oldest cloud goes.
    const auto oldest = std::find_if(pending_.begin(), pending_.end(),
                                     [](const Input& in) { return std::holds_alternative<rbcp_msgs::point_cloud_t>(in); });
    Reject(std::get<rbcp_msgs::point_cloud_t>(*oldest),
           "more than " + std::to_string(options_.max_pending_clouds) + " clouds came between two steps of the mapper");
    pending_.erase(oldest);
    --pending_clouds_;
  }
}

void TerrainMapperNode::CountMissed(const rbcp_msgs::point_cloud_t& msg) {
  const auto last = last_seq_.find(msg.sensor);
  if (last != last_seq_.end() && msg.seq > last->second + 1) {
    const int64_t missed = msg.seq - last->second - 1;
    clouds_missed_ += missed;
    if (status_.verbose()) {
      std::fprintf(stderr, "[%s] POINT_CLOUD '%s': %lld clouds before seq %lld never came (%lld missed in all)\n",
                   kProcessName, msg.sensor.c_str(), static_cast<long long>(missed), static_cast<long long>(msg.seq),
                   static_cast<long long>(clouds_missed_));
    }
  }
  last_seq_[msg.sensor] = msg.seq;
}

void TerrainMapperNode::TakeControllerStatus(const rbcp_msgs::controller_status_t& msg) {
  // A wait is heard once: the controller repeats its status while it waits.
  if (!msg.awaiting_plan || msg.awaiting_since == last_wait_heard_) return;
  last_wait_heard_ = msg.awaiting_since;
  pending_.emplace_back(msg.awaiting_since);
}

void TerrainMapperNode::Reject(const rbcp_msgs::point_cloud_t& msg, const std::string& why) {
  clouds_rejected_ += 1;
  status_.Failed(std::max<int64_t>(newest_cloud_utime_, 0), msg.utime, 0.0, why);
}

void TerrainMapperNode::IntegrateIfPlaced(const rbcp_msgs::point_cloud_t& msg) {
  if (newest_state_utime_ >= 0 && msg.utime - newest_state_utime_ > static_cast<int64_t>(options_.max_cloud_lead_s * 1e6)) {
    Reject(msg, "POINT_CLOUD '" + msg.sensor + "' " + std::to_string(msg.seq) + " is from " +
                    FixedNumber(Seconds(msg.utime), 3) + " s, more than " + FixedNumber(options_.max_cloud_lead_s, 2) +
                    " s after the newest ROBOT_STATE (" + FixedNumber(Seconds(newest_state_utime_), 3) + " s)");
    return;
  }
  Integrate(msg);
}

void TerrainMapperNode::Integrate(const rbcp_msgs::point_cloud_t& msg) {
  const auto start = std::chrono::steady_clock::now();
  status_.Busy(std::max<int64_t>(newest_cloud_utime_, 0), msg.utime);
  const Eigen::Isometry3d base_W = PoseOf(msg.base_position, msg.base_orientation);
  const Eigen::Isometry3d sensor_W = base_W * PoseOf(msg.mount_position, msg.mount_orientation);

  mapping::WorldCloud cloud;
  cloud.origin = sensor_W.translation();
  cloud.range_noise_std = msg.range_noise_std;
  cloud.points.reserve(msg.points.size());
  for (const auto& p : msg.points) {
    cloud.points.push_back(sensor_W * Eigen::Vector3d(p[0], p[1], p[2]));  // NaN stays NaN: the map skips it
  }
  map_.Recenter(base_W.translation().head<2>());
  const mapping::IntegrateReport report = map_.Integrate(cloud);
  // No sensor looks under the trunk: a new map starts with the ground the robot stands on, the
  // plane through its feet where its reference stance puts them under the base pose of its first
  // cloud (the robot starts standing; it may be dropped the last millimetres).
  if (!footprint_done_) {
    std::vector<Eigen::Vector3d> feet;
    for (Leg leg : kAllLegs) feet.push_back(base_W * robot_.ReferenceFootPosition(leg));
    map_.InitializeFootprint(feet, options_.footprint_margin_m, options_.footprint_variance_m2);
    footprint_done_ = true;
  }
  clouds_fused_ += 1;
  newest_cloud_utime_ = std::max(newest_cloud_utime_, msg.utime);
  dirty_ = true;
  integrate_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (report.points_invalid > 0 && status_.verbose()) {
    std::fprintf(stderr, "[%s] POINT_CLOUD '%s' %lld: %zu points not finite, skipped\n", kProcessName,
                 msg.sensor.c_str(), static_cast<long long>(msg.seq), report.points_invalid);
  }
  // The map goes out when its clouds' time reaches the next period.
  if (msg.utime >= next_publish_utime_) {
    const int64_t period = static_cast<int64_t>(std::llround(config_.publish_period_s * 1e6));
    next_publish_utime_ = (msg.utime / period + 1) * period;
    Publish(msg.utime, integrate_ms_);
  }
}

void TerrainMapperNode::Publish(int64_t utime, double compute_ms) {
  const auto start = std::chrono::steady_clock::now();
  const mapping::ElevationMap& grid = map_.elevation();
  if (grid.KnownCells() == 0) return;
  const TriangleMesh mesh = map_.ToMesh();
  if (mesh.Empty()) return;
  const auto terrain = transport::ToTerrainMsg(mesh, utime, "");
  const rbcp_msgs::elevation_map_t em = ToElevationMapMsg(grid, utime, terrain.terrain_id, clouds_fused_, clouds_missed_);
  std::string problem = publisher_.Publish(channels_.terrain, terrain);
  if (problem.empty()) problem = publisher_.Publish(channels_.elevation_map, em);
  last_terrain_ = terrain;
  const double ms =
      compute_ms + std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  integrate_ms_ = 0.0;
  dirty_ = false;
  published_utime_ = utime;
  if (!problem.empty()) {
    status_.Failed(utime, utime, ms, problem);
    return;
  }
  maps_published_ += 1;
  status_.Ok(utime, utime, ms,
             std::to_string(grid.KnownCells()) + " cells known, " + std::to_string(mesh.NumTriangles()) +
                 " triangles, " + std::to_string(clouds_fused_) + " clouds" +
                 (clouds_missed_ > 0 ? " (" + std::to_string(clouds_missed_) + " never came)" : std::string()) + ", " +
                 FixedNumber(static_cast<double>(map_.MemoryBytes()) / (1024.0 * 1024.0), 1) + " MB");
}

bool TerrainMapperNode::Step() {
  const bool worked = !pending_.empty();
  for (; !pending_.empty(); pending_.pop_front()) {
    if (const auto* cloud = std::get_if<rbcp_msgs::point_cloud_t>(&pending_.front())) {
      --pending_clouds_;
      IntegrateIfPlaced(*cloud);
    } else {
      PublishWait(std::get<int64_t>(pending_.front()));
    }
  }
  return worked;
}

void TerrainMapperNode::PublishWait(int64_t wait) {
  // The robot waits at a step boundary: every cloud up to the wait is in (the simulator sends a
  // tick's clouds before its status), and the map of the wait goes out (its utime the wait's), for
  // the planners to answer the wait on.
  if (published_utime_ != wait || dirty_) Publish(wait, integrate_ms_);
}

void TerrainMapperNode::Heartbeat() {
  status_.Heartbeat(std::max<int64_t>(newest_cloud_utime_, 0));
  // The latest map again, unchanged, for a process that started after it went out (while the
  // world stands still no new one comes).
  if (last_terrain_) publisher_.Publish(channels_.terrain, *last_terrain_);
}

}  // namespace rbcp::nodes
