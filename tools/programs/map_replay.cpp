// map_replay: a perceived run's LCM log (tools/launch --terrain perceived records it) replayed into
// a terrain mapper of its own, in this process: every map the run's terrain_mapper sent (TERRAIN,
// its utime and terrain_id) up to the simulator's verdict must come again, in the same order (the
// replayed mapper may send more before the verdict: the run's was stopped with the pipeline while
// clouds were on their way). The mapper's
// inputs (POINT_CLOUD, ROBOT_STATE, CONTROLLER_STATUS) go in in the log's order, one at a time, as
// they reached it. A cloud lost on the way (to the run's mapper or to the recorder: its mapper
// counts the gap in the sensor's seq on ELEVATION_MAP) makes the maps after it incomparable; the
// maps before the first difference are then compared and the loss reported (exit status 3).
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "log_messages.h"
#include "rbcp/cli/cli.h"
#include "rbcp/core/error.h"
#include "rbcp/mapping/terrain_map.h"
#include "rbcp/nodes/terrain_mapper_node.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/wire_check.h"
#include "rbcp_msgs/elevation_map_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace {

using namespace rbcp;

struct Options {
  cli::CommonOptions common;
  std::string log_path, config_path;
};

void AddOptions(CLI::App& app, Options& o) {
  cli::AddOfflineOptions(app, o.common);
  app.add_option("--log", o.log_path, "the LCM log of a run with --terrain perceived")->required()->check(CLI::ExistingFile);
  app.add_option("--config", o.config_path, "mapper parameters (default: CONFIG_DIR/mapper.yaml)");
  app.description(
      "Replays a perceived run's LCM log into a terrain mapper of its own (in this process): every map the run's\n"
      "terrain_mapper sent on TERRAIN (utime and terrain_id) up to the simulator's verdict must come again, in the\n"
      "same order. Reads a file; talks no LCM.\n"
      "Exit status: 0 the same maps, 1 a map differs (the first difference is printed), 2 bad input, 3 the maps\n"
      "differ after a cloud that the run's mapper or the recorder never received (the maps before are the same).");
}

/// A map as TERRAIN carries it; a repeat of the previous one (the mapper repeats its latest map
/// every second) is no new map.
using Map = std::pair<int64_t, int64_t>;  // utime, terrain_id
void AddMap(std::vector<Map>& maps, const Map& map) {
  if (maps.empty() || maps.back() != map) maps.push_back(map);
}

/// The clouds a mapper missed (ELEVATION_MAP clouds_missed), the most it reported.
void NoteMissed(int64_t& missed, const void* data, std::size_t size, long& malformed) {
  rbcp_msgs::elevation_map_t msg;
  if (transport::DecodeMessage(data, size, msg)) {
    ++malformed;
  } else {
    missed = std::max(missed, msg.clouds_missed);
  }
}

int Run(const Options& o) {
  struct Input {
    std::string channel;
    std::vector<uint8_t> bytes;
  };
  std::vector<Input> inputs;
  std::vector<Map> recorded;
  bool perceived = false;
  long malformed = 0;
  int64_t run_missed = 0;      // clouds the run's mapper never received
  int64_t verdict_utime = -1;  // the simulator's first OK or FAILED
  logs::ReadLogMessages(
      o.log_path,
      [&](int64_t, const std::string& channel, const void* data, std::size_t size) {
        if (channel == channels::kPointCloud || channel == channels::kRobotState || channel == channels::kControllerStatus) {
          const auto* b = static_cast<const uint8_t*>(data);
          inputs.push_back({channel, std::vector<uint8_t>(b, b + size)});
        } else if (channel == channels::kTerrainTruth) {
          perceived = true;
        } else if (channel == channels::kStatus) {
          rbcp_msgs::process_status_t msg;
          const bool decided = !transport::DecodeMessage(data, size, msg) && msg.process == "anymal_sim" &&
                               (msg.state == rbcp_msgs::process_status_t::OK || msg.state == rbcp_msgs::process_status_t::FAILED);
          if (decided && verdict_utime < 0) verdict_utime = msg.utime;
        } else if (channel == channels::kElevationMap) {
          NoteMissed(run_missed, data, size, malformed);
        } else if (channel == channels::kTerrain) {
          rbcp_msgs::terrain_mesh_t msg;
          if (transport::DecodeMessage(data, size, msg)) {
            ++malformed;
          } else {
            AddMap(recorded, {msg.utime, msg.terrain_id});
          }
        }
      },
      [&](const std::string&) { ++malformed; });
  if (!perceived) throw InputError(o.log_path + ": no TERRAIN_TRUTH: not a run with --terrain perceived");
  if (recorded.empty()) throw InputError(o.log_path + ": the mapper sent no map in this run");

  const auto config = mapping::MapperConfig::LoadFile(o.config_path.empty() ? o.common.config_dir + "/mapper.yaml" : o.config_path);
  const RobotModel robot = RobotModel::LoadDefault(o.common.config_dir);
  lcm::LCM lcm("memq://");
  if (!lcm.good()) throw InputError("cannot open LCM memq://");
  std::vector<Map> replayed;
  transport::EveryMessage<rbcp_msgs::terrain_mesh_t> maps_out(
      lcm, channels::kTerrain, [&](const rbcp_msgs::terrain_mesh_t& m) { AddMap(replayed, {m.utime, m.terrain_id}); },
      [&](const std::string&) { ++malformed; });
  int64_t log_missed = 0;  // clouds the recorder never received (the replayed mapper's gaps)
  transport::EveryMessage<rbcp_msgs::elevation_map_t> grids_out(
      lcm, channels::kElevationMap,
      [&](const rbcp_msgs::elevation_map_t& m) { log_missed = std::max(log_missed, m.clouds_missed); },
      [&](const std::string&) { ++malformed; });
  nodes::TerrainMapperNode node(lcm, config, robot);
  node.status().set_verbose(false);
  const auto pump = [&] {
    while (lcm.handleTimeout(0) > 0) {
    }
  };
  for (const Input& in : inputs) {
    lcm.publish(in.channel, in.bytes.data(), static_cast<unsigned>(in.bytes.size()));
    pump();
    while (node.Step()) pump();
    pump();
  }
  std::cout << "map_replay: " << inputs.size() << " inputs replayed; the run's mapper sent " << recorded.size()
            << " maps, the replayed one " << replayed.size() << (malformed ? ", " + std::to_string(malformed) + " malformed messages" : "")
            << "\n";
  // The maps up to the verdict (all of them without one).
  const auto until_verdict = [&](std::vector<Map>& maps) {
    if (verdict_utime < 0) return;
    while (!maps.empty() && maps.back().first > verdict_utime) maps.pop_back();
  };
  until_verdict(recorded);
  until_verdict(replayed);
  // Every map the run's mapper sent, again. The replayed mapper may have more before the verdict:
  // the run's was stopped with the pipeline while clouds before the verdict were on their way.
  for (std::size_t i = 0; i < recorded.size(); ++i) {
    if (i < recorded.size() && i < replayed.size() && recorded[i] == replayed[i]) continue;
    const auto describe = [](const std::vector<Map>& maps, std::size_t k) {
      return k < maps.size() ? "utime " + std::to_string(maps[k].first) + " terrain_id " + std::to_string(maps[k].second)
                             : std::string("none");
    };
    std::cout << "map_replay: map " << i + 1 << " differs: the run's " << describe(recorded, i) << ", replayed "
              << describe(replayed, i) << "\n";
    if (run_missed == 0 && log_missed == 0) return 1;
    // The two mappers did not hear the same clouds: the maps after the first lost one differ.
    std::cout << "map_replay: clouds were lost on the way (" << run_missed << " never reached the run's mapper, " << log_missed
              << " never reached the recorder): the replayed mapper sent the same " << i
              << " maps before the first difference; the later ones are not comparable" << std::endl;
    return 3;
  }
  std::cout << "map_replay: the replayed mapper sent the same " << recorded.size() << " maps"
            << (verdict_utime >= 0 ? " up to the simulator's verdict" : "") << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("map_replay", argc, argv, AddOptions, Run); }
