#include "rbcp/fuzz/fuzz_entries.h"

#include <boost/beast/_experimental/test/stream.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <functional>
#include <limits>

#include "rbcp/core/error.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/nodes/supervisor.h"
#include "rbcp/page_socket.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/sim/world_events.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/wire_check.h"

namespace rbcp::fuzz {
namespace {

// The limits the nodes apply by default (RootPlannerNodeOptions::max_time_budget_s,
// ContactPlannerNodeOptions::max_path_duration_s).
constexpr double kMaxTimeBudget_s = 60.0;
constexpr double kMaxPathDuration_s = 3600.0;

/// A scenario is read as if from a file in this folder: its relative mesh paths resolve against
/// the scenario tests' data (meshes/ramp.stl and the others).
const std::string kScenarioPath = std::string(RBCP_FUZZ_SCENARIO_DIR) + "/fuzz_input.yaml";

std::string Text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs `read`: accepted when it returns, rejected when it throws InputError.
Outcome Guard(const std::function<void()>& read) {
  try {
    read();
  } catch (const InputError& e) {
    return {false, e.what()};
  }
  return {true, ""};
}

Outcome ReadScenario(const std::uint8_t* data, std::size_t size) {
  return Guard([&] { ParseScenario(Text(data, size), kScenarioPath); });
}

Outcome Mesh(const std::uint8_t* data, std::size_t size, const char* path) {
  return Guard([&] { ParseMeshFile(Text(data, size), path, 1.0); });
}
Outcome ReadMeshStl(const std::uint8_t* data, std::size_t size) { return Mesh(data, size, "fuzz_input.stl"); }
Outcome ReadMeshObj(const std::uint8_t* data, std::size_t size) { return Mesh(data, size, "fuzz_input.obj"); }
Outcome ReadMeshPly(const std::uint8_t* data, std::size_t size) { return Mesh(data, size, "fuzz_input.ply"); }

Outcome ReadPlanJson(const std::uint8_t* data, std::size_t size) {
  return Guard([&] { ParseContactPlanJson(Text(data, size), "fuzz_input.json"); });
}

/// A message as a node's subscription decodes it (transport::DecodeMessage), then `validate`d as
/// the node does before using it.
template <typename Msg>
Outcome Message(const std::uint8_t* data, std::size_t size, const std::function<void(const Msg&)>& validate) {
  Msg msg;
  if (auto problem = transport::DecodeMessage(data, size, msg)) return {false, *problem};
  return Guard([&] { validate(msg); });
}

Outcome ReadTerrainMesh(const std::uint8_t* data, std::size_t size) {
  return Message<rbcp_msgs::terrain_mesh_t>(data, size, [](const auto& m) { transport::FromTerrainMsg(m); });
}

Outcome ReadAffordanceSet(const std::uint8_t* data, std::size_t size) {
  return Message<rbcp_msgs::affordance_set_t>(data, size, [](const auto& m) { transport::FromAffordanceMsg(m); });
}

Outcome ReadPlanRequest(const std::uint8_t* data, std::size_t size) {
  return Message<rbcp_msgs::plan_request_t>(data, size, [](const auto& m) {
    if (auto problem = transport::CheckPlanRequest(m, kMaxTimeBudget_s)) throw InputError(problem->Describe());
  });
}

Outcome ReadRobotState(const std::uint8_t* data, std::size_t size) {
  return Message<rbcp_msgs::robot_state_t>(data, size, [](const auto& m) { transport::FromRobotStateMsg(m); });
}

Outcome ReadControllerStatus(const std::uint8_t* data, std::size_t size) {
  return Message<rbcp_msgs::controller_status_t>(data, size,
                                                 [](const auto& m) { transport::FromControllerStatusMsg(m); });
}

Outcome ReadRootPath(const std::uint8_t* data, std::size_t size) {
  return Message<rbcp_msgs::root_path_t>(data, size,
                                         [](const auto& m) { transport::FromRootPathMsg(m, kMaxPathDuration_s); });
}

Outcome ReadContactPlan(const std::uint8_t* data, std::size_t size) {
  return Message<rbcp_msgs::contact_plan_t>(data, size, [](const auto& m) { transport::FromContactPlanMsg(m); });
}

Outcome ReadProcessStatus(const std::uint8_t* data, std::size_t size) {
  // The supervisor and the operator read the process name, pid and state as they come.
  return Message<rbcp_msgs::process_status_t>(data, size, [](const auto&) {});
}

/// A sequence of TERRAIN/PART messages (SplitPartRecords) put back together as a subscription
/// does (PartAssembler with the nodes' bound), and each whole message read as TERRAIN.
Outcome ReadMessageParts(const std::uint8_t* data, std::size_t size) {
  transport::PartAssembler assembler("TERRAIN");
  Outcome outcome{false, "no whole message"};
  for (const auto& [begin, length] : SplitPartRecords(data, size)) {
    std::string problem;
    const auto whole = assembler.Add(data + begin, length, problem);
    if (!problem.empty()) outcome = {false, problem};
    if (whole) outcome = ReadTerrainMesh(whole->data(), whole->size());
  }
  return outcome;
}

Outcome ReadWorldEvents(const std::uint8_t* data, std::size_t size) {
  return Guard([&] { sim::ParseWorldEvents(Text(data, size), "fuzz_input.yaml"); });
}

Outcome ReadSupervisorSpec(const std::uint8_t* data, std::size_t size) {
  return Guard([&] { nodes::SupervisorSpec::Load(YamlMap::Parse(Text(data, size), "fuzz_input.yaml")); });
}

/// Bytes a client sends to live_bridge: one HTTP request read with the bridge's bounds and, when it
/// asks for a websocket, the handshake and every frame after it read as a page's session reads
/// them, until the bytes end or the session fails. Accepted when at least one message came whole.
/// A read buffer beyond the bridge's bound is a bug (abort): the bound is what the target checks.
Outcome ServePageBytes(const std::uint8_t* data, std::size_t size) {
  namespace beast = boost::beast;
  namespace http = beast::http;
  namespace websocket = beast::websocket;
  boost::asio::io_context io;
  beast::test::stream server(io, beast::string_view(reinterpret_cast<const char*>(data), size));
  beast::test::stream client(io);
  server.connect(client);
  client.close();  // the client's bytes end where the input does

  // The request is read a byte at a time, so that the frames after it stay in the stream for the
  // websocket (the bridge's client sends none before the handshake's answer).
  server.read_size(1);
  beast::flat_buffer buffer;
  http::request_parser<http::string_body> parser;
  live_bridge::BoundRequest(parser);
  beast::error_code error;
  http::read(server, buffer, parser, error);
  if (error) return {false, "HTTP request: " + error.message()};
  server.read_size(std::numeric_limits<std::size_t>::max());
  const http::request<http::string_body> request = parser.release();
  if (!websocket::is_upgrade(request)) return {false, "not a websocket upgrade"};

  websocket::stream<beast::test::stream&> ws(server);
  live_bridge::ConfigurePageSocket(ws);
  ws.accept(request, error);
  if (error) return {false, "websocket handshake: " + error.message()};
  Outcome outcome{false, "no whole message"};
  for (;;) {
    beast::flat_buffer message;
    ws.read(message, error);
    if (message.size() > live_bridge::kMaxPageMessageBytes) std::abort();
    if (error) {
      if (!outcome.accepted) outcome.reason = "websocket: " + error.message();
      return outcome;
    }
    outcome = {true, ""};
  }
}

}  // namespace

const std::vector<Entry>& Entries() {
  static const std::vector<Entry> entries = {
      {"scenario", "scenario YAML text: ParseScenario (LoadScenario without the file)", ReadScenario},
      {"mesh_stl", "STL bytes: ParseMeshFile (LoadMeshFile without the file)", ReadMeshStl},
      {"mesh_obj", "OBJ bytes: ParseMeshFile (LoadMeshFile without the file)", ReadMeshObj},
      {"mesh_ply", "PLY bytes: ParseMeshFile (LoadMeshFile without the file)", ReadMeshPly},
      {"plan_json", "plan JSON text: ParseContactPlanJson (LoadContactPlanFile without the file)", ReadPlanJson},
      {"lcm_terrain_mesh", "TERRAIN message: DecodeMessage, FromTerrainMsg", ReadTerrainMesh},
      {"lcm_affordance_set", "AFFORDANCES message: DecodeMessage, FromAffordanceMsg", ReadAffordanceSet},
      {"lcm_plan_request", "PLAN_REQUEST message: DecodeMessage, CheckPlanRequest", ReadPlanRequest},
      {"lcm_robot_state", "ROBOT_STATE message: DecodeMessage, FromRobotStateMsg", ReadRobotState},
      {"lcm_controller_status", "CONTROLLER_STATUS message: DecodeMessage, FromControllerStatusMsg",
       ReadControllerStatus},
      {"lcm_root_path", "ROOT_PATH message: DecodeMessage, FromRootPathMsg", ReadRootPath},
      {"lcm_contact_plan", "CONTACT_PLAN message: DecodeMessage, FromContactPlanMsg", ReadContactPlan},
      {"lcm_process_status", "STATUS message: DecodeMessage", ReadProcessStatus},
      {"lcm_message_part", "TERRAIN/PART messages, each after a 2-byte length: PartAssembler, then as TERRAIN",
       ReadMessageParts},
      {"world_events", "events file YAML text: sim::ParseWorldEvents (LoadWorldEvents without the file)",
       ReadWorldEvents},
      {"supervisor_spec", "supervisor spec YAML text: SupervisorSpec::Load (LoadFile without the file)",
       ReadSupervisorSpec},
      {"websocket_frames", "a client's bytes to live_bridge: HTTP request, websocket handshake and frames",
       ServePageBytes},
  };
  return entries;
}

std::vector<std::pair<std::size_t, std::size_t>> SplitPartRecords(const std::uint8_t* data, std::size_t size) {
  std::vector<std::pair<std::size_t, std::size_t>> records;
  std::size_t at = 0;
  while (size - at >= 2) {
    const std::size_t length = std::min<std::size_t>(data[at] | (std::size_t{data[at + 1]} << 8), size - at - 2);
    records.emplace_back(at + 2, length);
    at += 2 + length;
  }
  return records;
}

const Entry* FindEntry(const std::string& name) {
  for (const Entry& e : Entries()) {
    if (name == e.name) return &e;
  }
  return nullptr;
}

}  // namespace rbcp::fuzz
