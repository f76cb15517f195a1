#include "rbcp/transport/wire_check.h"

#include <array>
#include <climits>
#include <cstring>
#include <vector>

namespace rbcp::transport {

/// One field of an encoded LCM struct, in the order of its .lcm file (big-endian, no padding).
struct WireField {
  enum class Kind {
    kBytes,   ///< fixed-size data: `bytes` long
    kCount,   ///< an int32 array count, named by the arrays that use it
    kString,  ///< int32 length (with the terminating NUL, so >= 1), then that many bytes
    kArray,   ///< `count` elements of `bytes` each, or of the struct `element`
  };
  Kind kind;
  const char* name;
  int64_t bytes = 0;
  const char* count = nullptr;
  const WireLayout* element = nullptr;
};

struct WireLayout {
  const char* name;
  std::vector<WireField> fields;
};

namespace {

constexpr int64_t kInt8 = 1, kInt32 = 4, kInt64 = 8, kDouble = 8, kBoolean = 1;
constexpr std::size_t kMaxFields = 32;

WireField Bytes(const char* name, int64_t bytes) { return {WireField::Kind::kBytes, name, bytes}; }
WireField Count(const char* name) { return {WireField::Kind::kCount, name, kInt32}; }
WireField String(const char* name) { return {WireField::Kind::kString, name}; }
WireField Array(const char* name, const char* count, int64_t element_bytes) {
  return {WireField::Kind::kArray, name, element_bytes, count};
}
WireField Array(const char* name, const char* count, const WireLayout& element) {
  return {WireField::Kind::kArray, name, 0, count, &element};
}

// The layouts below follow lcmtypes/*.lcm field by field; transport_tests encode every type with
// lcm-gen's encoder and check that these layouts consume exactly its bytes.

const WireLayout kAffordanceSurface{"affordance_surface_t",
                                    {Bytes("id", kInt32), Count("num_vertices"),
                                     Array("vertices", "num_vertices", 3 * kDouble), Bytes("normal", 3 * kDouble),
                                     Bytes("area", kDouble)}};

const WireLayout kAffordanceSet{
    "affordance_set_t",
    {Bytes("utime", kInt64), Bytes("terrain_id", kInt64), Count("num_surfaces"),
     Array("surfaces", "num_surfaces", kAffordanceSurface)}};

const WireLayout kTerrainMesh{"terrain_mesh_t",
                              {Bytes("utime", kInt64), String("scenario_name"), Bytes("terrain_id", kInt64),
                               Count("num_vertices"),
                               Array("vertices", "num_vertices", 3 * kDouble), Count("num_triangles"),
                               Array("triangles", "num_triangles", 3 * kInt32)}};

const WireLayout kPlanRequest{"plan_request_t",
                              {Bytes("utime", kInt64), Bytes("request_id", kInt64), Bytes("use_start", kBoolean),
                               Bytes("start_position", 3 * kDouble), Bytes("start_yaw", kDouble),
                               Bytes("goal_position", 3 * kDouble), Bytes("goal_yaw", kDouble),
                               Bytes("time_budget", kDouble), Bytes("seed", kInt32)}};

const WireLayout kRobotState{
    "robot_state_t",
    {Bytes("utime", kInt64), Bytes("base_position", 3 * kDouble), Bytes("base_orientation", 4 * kDouble),
     Bytes("base_linear_velocity", 3 * kDouble), Bytes("base_angular_velocity", 3 * kDouble),
     Bytes("joint_position", 12 * kDouble), Bytes("joint_velocity", 12 * kDouble),
     Bytes("joint_torque", 12 * kDouble), Bytes("foot_contact", 4 * kBoolean), Bytes("foot_force", 12 * kDouble)}};

const WireLayout kControllerStatus{
    "controller_status_t",
    {Bytes("utime", kInt64), Bytes("plan_seq", kInt64), Bytes("steps_done", kInt32), Bytes("awaiting_plan", kBoolean),
     Bytes("awaiting_since", kInt64), String("phase"), Bytes("step", kInt32), Bytes("swing_leg", kInt8),
     Bytes("base_error", kDouble), Bytes("step_max_base_error", kDouble), Bytes("support_margin", kDouble),
     Bytes("steps_committed", kInt32), Bytes("lag_s", kDouble)}};

constexpr int64_t kRootPathPointBytes = kDouble + 3 * kDouble + 3 * kDouble + 4 * kDouble;
const WireLayout kRootPath{"root_path_t",
                           {Bytes("utime", kInt64), Bytes("request_id", kInt64), Bytes("terrain_id", kInt64),
                            Bytes("reaches_goal", kBoolean), Count("num_points"),
                            Array("points", "num_points", kRootPathPointBytes)}};

constexpr int64_t kWholeBodyStateBytes =
    3 * kDouble + 3 * kDouble + 12 * kDouble + 12 * kDouble + 12 * kDouble + kInt8 + kDouble + 2 * kDouble + 2 * kDouble;
const WireLayout kContactPlan{"contact_plan_t",
                              {Bytes("utime", kInt64), Bytes("request_id", kInt64), Bytes("terrain_id", kInt64),
                               Bytes("plan_seq", kInt64),
                               Bytes("start_utime", kInt64), Bytes("reaches_goal", kBoolean), Count("num_states"),
                               Array("states", "num_states", kWholeBodyStateBytes)}};

const WireLayout kProcessStatus{"process_status_t",
                                {Bytes("utime", kInt64), String("process"), Bytes("pid", kInt32),
                                 Bytes("state", kInt8), String("reason"), Bytes("input_utime", kInt64),
                                 Bytes("compute_ms", kDouble), Bytes("handled", kInt64)}};

const WireLayout kMessagePart{"message_part_t",
                               {Bytes("utime", kInt64), Bytes("sender", kInt64), Bytes("sequence", kInt64),
                                Bytes("checksum", kInt64), Bytes("total_size", kInt32), Bytes("part_count", kInt32),
                                Bytes("index", kInt32), Count("num_bytes"), Array("bytes", "num_bytes", kInt8)}};

constexpr int64_t kFloat = 4;
const WireLayout kPointCloud{"point_cloud_t",
                             {Bytes("utime", kInt64), String("sensor"), Bytes("seq", kInt64),
                              Bytes("base_position", 3 * kDouble), Bytes("base_orientation", 4 * kDouble),
                              Bytes("mount_position", 3 * kDouble), Bytes("mount_orientation", 4 * kDouble),
                              Bytes("min_range", kFloat), Bytes("max_range", kFloat), Bytes("range_noise_std", kFloat),
                              Bytes("num_rays", kInt32), Count("num_points"), Array("points", "num_points", 3 * kFloat)}};

const WireLayout kElevationMap{"elevation_map_t",
                               {Bytes("utime", kInt64), Bytes("terrain_id", kInt64), Bytes("clouds_fused", kInt64),
                                Bytes("clouds_missed", kInt64), Bytes("origin", 2 * kDouble), Bytes("resolution", kDouble), Bytes("num_x", kInt32),
                                Bytes("num_y", kInt32), Count("num_cells"), Array("height", "num_cells", kFloat),
                                Array("variance", "num_cells", kFloat)}};

int32_t ReadInt32(const uint8_t* p) {
  const uint32_t v = (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
  int32_t out;
  std::memcpy(&out, &v, sizeof(out));
  return out;
}

int64_t ReadInt64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  int64_t out;
  std::memcpy(&out, &v, sizeof(out));
  return out;
}

/// The fewest bytes one encoded `layout` takes (every array empty, every string "").
int64_t MinimumSize(const WireLayout& layout) {
  int64_t total = 0;
  for (const WireField& f : layout.fields) {
    if (f.kind == WireField::Kind::kString) total += kInt32 + 1;
    if (f.kind == WireField::Kind::kBytes || f.kind == WireField::Kind::kCount) total += f.bytes;
  }
  return total;
}

/// Walks one encoded `layout` from `pos`, advancing it; nullopt, or the first field that does not fit.
std::optional<std::string> Walk(const WireLayout& layout, const uint8_t* data, int64_t size, int64_t& pos) {
  std::array<int64_t, kMaxFields> counts{};
  if (layout.fields.size() > kMaxFields) return std::string(layout.name) + ": too many fields for the wire check";
  const auto need = [&](int64_t bytes, const std::string& what) -> std::optional<std::string> {
    if (bytes <= size - pos) return std::nullopt;
    return std::string(layout.name) + ": " + what + " needs " + std::to_string(bytes) + " bytes, " +
           std::to_string(size - pos) + " remain";
  };
  for (std::size_t i = 0; i < layout.fields.size(); ++i) {
    const WireField& f = layout.fields[i];
    switch (f.kind) {
      case WireField::Kind::kBytes:
        if (auto e = need(f.bytes, f.name)) return e;
        pos += f.bytes;
        break;
      case WireField::Kind::kCount: {
        if (auto e = need(kInt32, f.name)) return e;
        counts[i] = ReadInt32(data + pos);
        pos += kInt32;
        if (counts[i] < 0) {
          return std::string(layout.name) + ": " + f.name + " " + std::to_string(counts[i]) + " is negative";
        }
        break;
      }
      case WireField::Kind::kString: {
        if (auto e = need(kInt32, std::string("the length of ") + f.name)) return e;
        const int64_t length = ReadInt32(data + pos);
        pos += kInt32;
        if (length < 1) {
          return std::string(layout.name) + ": " + f.name + " has length " + std::to_string(length) +
                 ", expected at least 1 (the terminating NUL)";
        }
        if (auto e = need(length, f.name)) return e;
        pos += length;
        break;
      }
      case WireField::Kind::kArray: {
        int64_t n = -1;
        for (std::size_t k = 0; k < i; ++k) {
          if (std::strcmp(layout.fields[k].name, f.count) == 0) n = counts[k];
        }
        if (n < 0) return std::string(layout.name) + ": no count field " + f.count + " before " + f.name;
        const int64_t element = f.element ? MinimumSize(*f.element) : f.bytes;
        // Every element takes at least `element` bytes: a claim beyond the bytes that remain is
        // rejected before anything is walked or allocated.
        if (n * element > size - pos) {
          return std::string(layout.name) + ": " + f.count + " " + std::to_string(n) + " claims at least " +
                 std::to_string(n * element) + " bytes of " + f.name + ", " + std::to_string(size - pos) + " remain";
        }
        if (!f.element) {
          pos += n * element;
          break;
        }
        for (int64_t k = 0; k < n; ++k) {
          if (auto e = Walk(*f.element, data, size, pos)) {
            return std::string(layout.name) + "." + f.name + "[" + std::to_string(k) + "]: " + *e;
          }
        }
        break;
      }
    }
  }
  return std::nullopt;
}

}  // namespace

const WireLayout& LayoutOf(const rbcp_msgs::terrain_mesh_t*) { return kTerrainMesh; }
const WireLayout& LayoutOf(const rbcp_msgs::affordance_set_t*) { return kAffordanceSet; }
const WireLayout& LayoutOf(const rbcp_msgs::plan_request_t*) { return kPlanRequest; }
const WireLayout& LayoutOf(const rbcp_msgs::robot_state_t*) { return kRobotState; }
const WireLayout& LayoutOf(const rbcp_msgs::controller_status_t*) { return kControllerStatus; }
const WireLayout& LayoutOf(const rbcp_msgs::root_path_t*) { return kRootPath; }
const WireLayout& LayoutOf(const rbcp_msgs::contact_plan_t*) { return kContactPlan; }
const WireLayout& LayoutOf(const rbcp_msgs::process_status_t*) { return kProcessStatus; }
const WireLayout& LayoutOf(const rbcp_msgs::message_part_t*) { return kMessagePart; }
const WireLayout& LayoutOf(const rbcp_msgs::point_cloud_t*) { return kPointCloud; }
const WireLayout& LayoutOf(const rbcp_msgs::elevation_map_t*) { return kElevationMap; }

std::optional<std::string> CheckEncoded(const void* data, std::size_t size, const WireLayout& layout, int64_t hash) {
  if (size > static_cast<std::size_t>(INT_MAX)) {
    return std::string(layout.name) + ": " + std::to_string(size) + " bytes, more than a message can hold";
  }
  const auto* bytes = static_cast<const uint8_t*>(data);
  if (size < static_cast<std::size_t>(kInt64)) {
    return std::string(layout.name) + ": " + std::to_string(size) + " bytes, shorter than the type's fingerprint";
  }
  if (ReadInt64(bytes) != hash) {
    return std::string("not a ") + layout.name + " (its fingerprint differs: another type or garbage)";
  }
  int64_t pos = kInt64;
  return Walk(layout, bytes, static_cast<int64_t>(size), pos);
}

}  // namespace rbcp::transport
