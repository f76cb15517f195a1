// fuzz_seeds: seed corpora of the LCM message targets and of plan_json from recorded LCM logs.
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "rbcp/core/error.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/wire_check.h"

namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

/// Seeds kept per target: evenly spread over the log, as a log repeats many similar messages.
constexpr std::size_t kMaxSeeds = 16;

int64_t Fingerprint(const Bytes& data) {
  uint64_t v = 0;
  for (std::size_t i = 0; i < 8 && i < data.size(); ++i) v = (v << 8) | data[i];
  int64_t out;
  std::memcpy(&out, &v, sizeof(out));
  return out;
}

/// The fuzz target of each message type, by its fingerprint.
const std::map<int64_t, std::string>& TargetsByFingerprint() {
  static const std::map<int64_t, std::string> targets = {
      {rbcp_msgs::terrain_mesh_t::getHash(), "lcm_terrain_mesh"},
      {rbcp_msgs::affordance_set_t::getHash(), "lcm_affordance_set"},
      {rbcp_msgs::plan_request_t::getHash(), "lcm_plan_request"},
      {rbcp_msgs::robot_state_t::getHash(), "lcm_robot_state"},
      {rbcp_msgs::controller_status_t::getHash(), "lcm_controller_status"},
      {rbcp_msgs::root_path_t::getHash(), "lcm_root_path"},
      {rbcp_msgs::contact_plan_t::getHash(), "lcm_contact_plan"},
      {rbcp_msgs::process_status_t::getHash(), "lcm_process_status"},
  };
  return targets;
}

void Write(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

/// Plan states in a JSON seed: a few, as the targets' inputs are kept short.
constexpr std::size_t kMaxPlanStates = 2;

/// The JSON seeds of a recorded plan's first states: the bare array and the document form.
std::vector<std::string> PlanJsonSeeds(const Bytes& data) {
  rbcp_msgs::contact_plan_t msg;
  if (rbcp::transport::DecodeMessage(data.data(), data.size(), msg)) return {};
  try {
    rbcp::ContactPlan plan = rbcp::transport::FromContactPlanMsg(msg);
    plan.states.resize(std::min(plan.states.size(), kMaxPlanStates));
    const nlohmann::json states = rbcp::ContactPlanToJson(plan);
    return {states.dump(), nlohmann::json{{"states", states}, {"steps", msg.num_states}}.dump(1)};
  } catch (const rbcp::InputError&) {
    return {};
  }
}

/// The lcm_message_part seed of an encoded TERRAIN message: its parts (of at most 512 bytes, as
/// a MessagePublisher cuts them), each after its 2-byte little-endian length.
std::string PartSeed(const Bytes& terrain) {
  lcm::LCM lcm("memq://");
  std::string records;
  lcm::Subscription* sub = lcm.subscribeFunction(
      rbcp::transport::PartChannel("TERRAIN"),
      +[](const lcm::ReceiveBuffer* rbuf, const std::string&, std::string* out) {
        out->push_back(static_cast<char>(rbuf->data_size & 0xff));
        out->push_back(static_cast<char>((rbuf->data_size >> 8) & 0xff));
        out->append(static_cast<const char*>(rbuf->data), rbuf->data_size);
      },
      &records);
  rbcp::transport::PartOptions options;
  options.threshold_bytes = 0;
  options.part_bytes = 512;
  options.pause_s = 0.0;
  options.sender = 1;
  rbcp::transport::MessagePublisher publisher(lcm, options);
  if (!publisher.PublishEncoded("TERRAIN", terrain.data(), terrain.size()).empty()) return "";
  while (lcm.handleTimeout(0) > 0) {
  }
  lcm.unsubscribe(sub);
  return records;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage = "Usage: fuzz_seeds OUT_DIR LOG.lcmlog...";
  if (argc >= 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::cout << "Writes seed inputs of the fuzz targets from recorded LCM logs: up to " << kMaxSeeds
              << " messages of each type\n(OUT_DIR/lcm_TYPE/), the small terrains in parts (OUT_DIR/lcm_message_part/) and "
                 "the recorded contact plans\nas plan JSON (OUT_DIR/plan_json/).\nReads files; talks no LCM.\n"
              << usage << "\n";
    return 0;
  }
  if (argc < 3 || argv[1][0] == '-') {
    std::cerr << "fuzz_seeds: " << usage << std::endl;
    return 2;
  }
  const fs::path out_dir = argv[1];
  std::map<std::string, std::vector<std::pair<std::string, Bytes>>> messages;  // target -> (name, bytes)
  for (int a = 2; a < argc; ++a) {
    const std::string log_path = argv[a];
    lcm::LogFile log(log_path, "r");
    if (!log.good()) {
      std::cerr << "fuzz_seeds: cannot read the LCM log " << log_path << std::endl;
      return 1;
    }
    std::set<Bytes> seen;
    long index = 0;
    while (const lcm::LogEvent* e = log.readNextEvent()) {
      const auto* begin = static_cast<const std::uint8_t*>(e->data);
      Bytes data(begin, begin + e->datalen);
      const auto target = TargetsByFingerprint().find(Fingerprint(data));
      if (target == TargetsByFingerprint().end() || !seen.insert(data).second) continue;
      const std::string name = fs::path(log_path).stem().string() + "-" + std::to_string(index++);
      messages[target->second].emplace_back(name, std::move(data));
    }
  }
  try {
    for (const auto& [target, list] : messages) {
      const std::size_t n = std::min(list.size(), kMaxSeeds);
      for (std::size_t k = 0; k < n; ++k) {
        const auto& [name, data] = list[k * list.size() / n];
        Write(out_dir / target / name, std::string(data.begin(), data.end()));
        if (target == "lcm_terrain_mesh" && data.size() <= 8192) {
          const std::string parts = PartSeed(data);
          if (!parts.empty()) Write(out_dir / "lcm_message_part" / name, parts);
        }
        if (target != "lcm_contact_plan") continue;
        const std::vector<std::string> plans = PlanJsonSeeds(data);
        for (std::size_t p = 0; p < plans.size(); ++p) {
          Write(out_dir / "plan_json" / (name + "-" + std::to_string(p) + ".json"), plans[p]);
        }
      }
      std::cout << "fuzz_seeds: " << target << ": " << n << " of " << list.size() << " distinct messages\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "fuzz_seeds: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
