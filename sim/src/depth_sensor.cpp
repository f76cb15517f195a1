// Simulated depth sensors: pinhole grids of rays cast against the terrain, with seeded range noise.

#include "rbcp/sim/depth_sensor.h"

#include <cmath>
#include <random>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/sim/bullet_world.h"

namespace rbcp::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// SplitMix64's finaliser: spreads the bits of one 64-bit word over all of them.
std::uint64_t Mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// The front camera's mount: on the trunk's front end (the trunk box reaches x = 0.266 m, its top
/// z = 0.20 m), pitched down 0.72 rad so that, standing at the nominal base height (0.456 m),
/// the image's bottom edge meets the ground 0.5 m ahead of the base (just ahead of the front
/// feet) and its top edge 2.7 m ahead.
constexpr double kCameraX_m = 0.31;
constexpr double kCameraZ_m = 0.07;
constexpr double kCameraPitch_rad = 0.72;

}  // namespace

DepthSensorConfig DepthSensorConfig::Front() {
  DepthSensorConfig c;
  c.position = Eigen::Vector3d(kCameraX_m, 0.0, kCameraZ_m);
  c.rpy = Eigen::Vector3d(0.0, kCameraPitch_rad, 0.0);
  return c;
}

DepthSensorConfig DepthSensorConfig::Rear() {
  DepthSensorConfig c;
  c.position = Eigen::Vector3d(-kCameraX_m, 0.0, kCameraZ_m);
  c.rpy = Eigen::Vector3d(0.0, kCameraPitch_rad, M_PI);
  return c;
}

Eigen::Isometry3d DepthSensorConfig::Mount() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = RotationFromRpy(rpy);
  T.translation() = position;
  return T;
}

DepthSensor::DepthSensor(std::string name, int index, const DepthSensorConfig& config, double range_noise_m,
                         std::uint64_t noise_seed)
    : name_(std::move(name)),
      index_(index),
      config_(config),
      range_noise_m_(range_noise_m),
      noise_seed_(noise_seed),
      mount_(config.Mount()) {
  ValidateConfig(config_, "sensing: " + name_);
  if (!(range_noise_m_ >= 0.0) || !std::isfinite(range_noise_m_)) {
    throw InputError("sensing: 'range_noise_m': expected a non-negative number [m]");
  }
  // Pixel centres of a pinhole image: the image plane at x = 1 spans +-tan(fov / 2).
  const double half_w = std::tan(0.5 * config_.horizontal_fov_deg * kDegToRad);
  const double half_h = std::tan(0.5 * config_.vertical_fov_deg * kDegToRad);
  directions_.reserve(static_cast<std::size_t>(config_.columns) * static_cast<std::size_t>(config_.rows));
  for (int r = 0; r < config_.rows; ++r) {
    const double z = half_h * (1.0 - 2.0 * (r + 0.5) / config_.rows);
    for (int c = 0; c < config_.columns; ++c) {
      const double y = half_w * (1.0 - 2.0 * (c + 0.5) / config_.columns);
      directions_.push_back(Eigen::Vector3d(1.0, y, z).normalized());
    }
  }
}

PointCloud DepthSensor::Capture(const BulletWorld& world, const Eigen::Isometry3d& base_W, int64_t seq,
                                double t) const {
  PointCloud cloud;
  cloud.sensor = name_;
  cloud.seq = seq;
  cloud.t = t;
  cloud.mount = mount_;
  cloud.min_range_m = config_.min_range_m;
  cloud.max_range_m = config_.max_range_m;
  cloud.range_noise_m = range_noise_m_;
  cloud.num_rays = static_cast<int>(directions_.size());

  const Eigen::Isometry3d sensor_W = base_W * mount_;
  std::vector<Eigen::Vector3d> directions_W(directions_.size());
  for (std::size_t k = 0; k < directions_.size(); ++k) directions_W[k] = sensor_W.linear() * directions_[k];
  // Far enough for a return that the noise brings back inside max_range_m.
  const double cast_range = config_.max_range_m + 5.0 * range_noise_m_;
  std::vector<double> distances;
  world.CastTerrainRays(sensor_W.translation(), directions_W, cast_range, &distances);

  // One generator per capture, from (seed, sensor, seq): the draws do not depend on anything else.
  std::seed_seq seeds{static_cast<std::uint32_t>(Mix(noise_seed_)), static_cast<std::uint32_t>(Mix(noise_seed_) >> 32),
                      static_cast<std::uint32_t>(index_), static_cast<std::uint32_t>(Mix(static_cast<std::uint64_t>(seq))),
                      static_cast<std::uint32_t>(Mix(static_cast<std::uint64_t>(seq)) >> 32)};
  std::mt19937_64 rng(seeds);
  std::normal_distribution<double> noise(0.0, 1.0);
  cloud.points.reserve(directions_.size());
  for (std::size_t k = 0; k < directions_.size(); ++k) {
    if (!std::isfinite(distances[k])) continue;
    // A draw for every ray that met the terrain, kept or not: one ray's return does not shift
    // the noise of the next.
    const double range = distances[k] + range_noise_m_ * noise(rng);
    if (range < config_.min_range_m || range > config_.max_range_m) continue;
    cloud.points.push_back((range * directions_[k]).cast<float>());
  }
  return cloud;
}

SensorRig::SensorRig(const SensingConfig& config, double control_rate_hz) : control_rate_hz_(control_rate_hz) {
  if (!(control_rate_hz > 0.0) || !(config.rate_hz > 0.0)) {
    throw InputError("sensing: expected positive rates, got rate_hz " + ConfigNumber(config.rate_hz) +
                     " and a control rate of " + ConfigNumber(control_rate_hz) + " Hz");
  }
  ticks_per_capture_ = static_cast<int>(std::lround(control_rate_hz / config.rate_hz));
  if (ticks_per_capture_ < 1 || std::abs(ticks_per_capture_ * config.rate_hz - control_rate_hz) > 1e-6 * control_rate_hz) {
    throw InputError("sensing: 'rate_hz': expected a rate that divides control_rate_hz (" +
                     ConfigNumber(control_rate_hz) + " Hz), got " + ConfigNumber(config.rate_hz));
  }
  if (!config.enabled) return;
  if (config.front_camera.enabled) {
    sensors_.emplace_back("front_camera", 0, config.front_camera, config.range_noise_m, config.noise_seed);
  }
  if (config.rear_camera.enabled) {
    sensors_.emplace_back("rear_camera", 1, config.rear_camera, config.range_noise_m, config.noise_seed);
  }
}

std::vector<PointCloud> SensorRig::CaptureIfDue(const BulletWorld& world, const RobotState& state) {
  std::vector<PointCloud> clouds;
  if (sensors_.empty()) return clouds;
  const long long tick = std::llround(state.t * control_rate_hz_);
  if (tick == last_tick_ || tick % ticks_per_capture_ != 0) return clouds;
  last_tick_ = tick;
  seq_ += 1;
  Eigen::Isometry3d base_W = Eigen::Isometry3d::Identity();
  base_W.linear() = state.base_orientation_W.normalized().toRotationMatrix();
  base_W.translation() = state.base_position_W;
  clouds.reserve(sensors_.size());
  for (const DepthSensor& s : sensors_) clouds.push_back(s.Capture(world, base_W, seq_, state.t));
  return clouds;
}

}  // namespace rbcp::sim
