#pragma once
/// Bounded decoding of LCM messages. lcm-gen's decoders size every array from its count field
/// before they look at the bytes behind it, so a message of a few bytes that claims 2^31 elements
/// makes them allocate gigabytes. DecodeMessage first walks the encoding against the type's layout
/// (every count against the bytes that remain, every string length against its bytes) and only
/// decodes a message that holds all it claims: the allocation is bounded by the message's size.

#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>

#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/elevation_map_t.hpp"
#include "rbcp_msgs/message_part_t.hpp"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/point_cloud_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::transport {

struct WireLayout;  ///< the encoded layout of one message type (wire_check.cpp)

/// The layout of each message type of lcmtypes/ sent on a channel.
const WireLayout& LayoutOf(const rbcp_msgs::terrain_mesh_t*);
const WireLayout& LayoutOf(const rbcp_msgs::affordance_set_t*);
const WireLayout& LayoutOf(const rbcp_msgs::plan_request_t*);
const WireLayout& LayoutOf(const rbcp_msgs::robot_state_t*);
const WireLayout& LayoutOf(const rbcp_msgs::controller_status_t*);
const WireLayout& LayoutOf(const rbcp_msgs::root_path_t*);
const WireLayout& LayoutOf(const rbcp_msgs::contact_plan_t*);
const WireLayout& LayoutOf(const rbcp_msgs::process_status_t*);
const WireLayout& LayoutOf(const rbcp_msgs::message_part_t*);
const WireLayout& LayoutOf(const rbcp_msgs::point_cloud_t*);
const WireLayout& LayoutOf(const rbcp_msgs::elevation_map_t*);

/// nullopt when the `size` bytes at `data` are an encoding of `layout` with the fingerprint `hash` that
/// holds every element its counts and string lengths claim; otherwise why not, naming the field.
/// Takes time linear in `size` and allocates nothing.
std::optional<std::string> CheckEncoded(const void* data, std::size_t size, const WireLayout& layout, int64_t hash);

/// CheckEncoded for the message type Msg.
template <typename Msg>
std::optional<std::string> CheckEncoded(const void* data, std::size_t size) {
  return CheckEncoded(data, size, LayoutOf(static_cast<const Msg*>(nullptr)), Msg::getHash());
}

/// Decodes `size` bytes into `msg` once CheckEncoded accepts them. Returns nullopt on success,
/// otherwise why the bytes are no Msg (`msg` is then unspecified); never throws.
template <typename Msg>
std::optional<std::string> DecodeMessage(const void* data, std::size_t size, Msg& msg) {
  if (auto problem = CheckEncoded<Msg>(data, size)) return problem;
  try {
    if (msg.decode(data, 0, static_cast<int>(size)) < 0) return std::string("malformed");
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
  return std::nullopt;
}

}  // namespace rbcp::transport
