#pragma once
/// Simulated depth sensors fixed to the trunk (config/sim.yaml `sensing:`): ANYmal B's front and
/// rear depth cameras as pinhole grids of rays cast against the terrain.
///
/// A capture casts columns x rows rays from the sensor's origin, one through the centre of each
/// pixel of a pinhole image of horizontal_fov_deg x vertical_fov_deg (sensor frame: x along the
/// optical axis, y left, z up; column 0 on the left, row 0 at the top). A ray returns the first
/// terrain surface it meets: the true range plus Gaussian noise of range_noise_m along the ray,
/// kept when that noisy range lies in [min_range_m, max_range_m]. Rays see the terrain only,
/// never the robot's own links: this stands in for a perfect self-filter (a real robot removes
/// the returns from its legs from the cloud, and the legs' shadows on the ground are not
/// simulated either). The noise is deterministic: each capture draws from a generator seeded by
/// (noise_seed, the sensor's index, the capture's seq), so a run gives the same clouds whatever
/// else happens in it.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "rbcp/core/config_fields.h"
#include "rbcp/robot/robot_state.h"

namespace rbcp::sim {

class BulletWorld;

/// One depth sensor's mount and image (a map under `sensing:`).
struct DepthSensorConfig {
  bool enabled = true;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
  double horizontal_fov_deg = 87.0;
  double vertical_fov_deg = 58.0;
  int columns = 64;
  int rows = 40;
  double min_range_m = 0.3;
  double max_range_m = 3.5;

  static constexpr double kMaxFovDeg = 170.0;  ///< a pinhole image spans less than 180 degrees
  static constexpr int kMaxRays = 1 << 20;     ///< largest columns x rows

  /// The front camera's defaults: on the trunk's front end, looking ahead and down.
  static DepthSensorConfig Front();
  /// The rear camera's defaults: the front one mirrored, looking behind and down.
  static DepthSensorConfig Rear();

  /// The sensor frame in the base frame (sensor to base).
  Eigen::Isometry3d Mount() const;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("enabled", &enabled, "the sensor captures (with sensing.enabled)");
    v->Visit("position", &position, "m", bounds::Closed(-2.0, 2.0), "the sensor's origin in the base frame [x, y, z]");
    v->Visit("rpy", &rpy, "rad", bounds::Closed(-7.0, 7.0),
             "the sensor frame's orientation in the base frame (roll, pitch, yaw; x along the optical axis, y "
             "left, z up): a positive pitch looks down");
    v->Visit("horizontal_fov_deg", &horizontal_fov_deg, "deg", bounds::Positive().AtMost(kMaxFovDeg),
             "the image's horizontal field of view");
    v->Visit("vertical_fov_deg", &vertical_fov_deg, "deg", bounds::Positive().AtMost(kMaxFovDeg),
             "the image's vertical field of view");
    v->Visit("columns", &columns, "", bounds::Closed(1, 4096), "rays across the image (pixels of the subsampled image)");
    v->Visit("rows", &rows, "", bounds::Closed(1, 4096), "rays down the image");
    v->Rule("rows", static_cast<long long>(columns) * rows <= kMaxRays,
            "columns x rows at most " + std::to_string(kMaxRays), std::to_string(static_cast<long long>(columns) * rows));
    v->Visit("min_range_m", &min_range_m, "m", bounds::NonNegative(), "no return closer than this");
    v->Visit("max_range_m", &max_range_m, "m", bounds::Positive().AtMost(100.0), "no return farther than this");
    v->Rule("max_range_m", max_range_m > min_range_m, "a range above min_range_m", ConfigNumber(max_range_m));
  }
};

/// The simulated depth sensors (the `sensing` map of config/sim.yaml).
struct SensingConfig {
  bool enabled = true;
  double rate_hz = 10.0;
  double range_noise_m = 0.01;
  std::uint64_t noise_seed = 1;
  double look_before_walking_s = 1.0;
  DepthSensorConfig front_camera = DepthSensorConfig::Front();
  DepthSensorConfig rear_camera = DepthSensorConfig::Rear();

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("enabled", &enabled,
             "the robot carries the depth sensors: with a perceived terrain (anymal_sim --terrain perceived) they "
             "capture and POINT_CLOUD goes out");
    v->Visit("rate_hz", &rate_hz, "Hz", bounds::Positive(),
             "captures per second of simulated time, per sensor (must divide control_rate_hz)");
    v->Visit("range_noise_m", &range_noise_m, "m", bounds::Closed(0.0, 1.0),
             "1-sigma Gaussian range noise along each ray");
    v->Visit("noise_seed", &noise_seed, "", bounds::NonNegative(),
             "seeds the range noise: the same seed gives the same clouds (anymal_sim --sensor-seed)");
    v->Visit("look_before_walking_s", &look_before_walking_s, "s", bounds::Closed(0.0, 10.0),
             "on a perceived terrain the robot stands this long of simulated time, its sensors capturing, before "
             "it waits for its first plan (a robot looks around before it walks; the world stands still while it "
             "waits)");
    v->Visit("front_camera", &front_camera, "the front depth camera: on the trunk's front end, looking ahead and down");
    v->Visit("rear_camera", &rear_camera, "the rear depth camera: the front one mirrored, looking behind and down");
  }
};

/// One capture, points in the sensor frame.
struct PointCloud {
  std::string sensor;  ///< "front_camera", "rear_camera"
  int64_t seq = 0;     ///< this sensor's captures, from 1
  double t = 0.0;      ///< simulated time of the capture [s]
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();  ///< sensor to base
  double min_range_m = 0.0;
  double max_range_m = 0.0;
  double range_noise_m = 0.0;
  int num_rays = 0;
  std::vector<Eigen::Vector3f> points;  ///< [m] sensor frame, one per ray that returned
};

/// One depth sensor: a grid of rays fixed to the base.
class DepthSensor {
 public:
  /// `index` tells the sensor apart in the noise seed. Throws InputError for a bad config.
  DepthSensor(std::string name, int index, const DepthSensorConfig& config, double range_noise_m,
              std::uint64_t noise_seed);

  /// Casts the rays from the sensor posed at base_W * mount against the world's current terrain.
  /// `seq` numbers the capture (it seeds the noise with the sensor index and noise_seed).
  PointCloud Capture(const BulletWorld& world, const Eigen::Isometry3d& base_W, int64_t seq, double t) const;

  const std::string& Name() const { return name_; }
  const DepthSensorConfig& Config() const { return config_; }
  /// Unit ray directions in the sensor frame, row by row from the top left.
  const std::vector<Eigen::Vector3d>& Directions() const { return directions_; }

 private:
  std::string name_;
  int index_;
  DepthSensorConfig config_;
  double range_noise_m_;
  std::uint64_t noise_seed_;
  Eigen::Isometry3d mount_;
  std::vector<Eigen::Vector3d> directions_;
};

/// The robot's enabled sensors and their schedule: every 1/rate_hz of simulated time (on the
/// control tick at that time) each captures once; the same tick never twice.
class SensorRig {
 public:
  /// No sensor when sensing is disabled. Throws InputError for a bad config.
  SensorRig(const SensingConfig& config, double control_rate_hz);

  /// The captures due at the state's time: one cloud per enabled sensor from the state's base
  /// pose, or none (not a capture tick, or this tick was captured already).
  std::vector<PointCloud> CaptureIfDue(const BulletWorld& world, const RobotState& state);

  bool Empty() const { return sensors_.empty(); }
  const std::vector<DepthSensor>& Sensors() const { return sensors_; }
  int TicksPerCapture() const { return ticks_per_capture_; }

 private:
  std::vector<DepthSensor> sensors_;
  double control_rate_hz_;
  int ticks_per_capture_ = 1;
  long long last_tick_ = -1;
  int64_t seq_ = 0;
};

}  // namespace rbcp::sim
