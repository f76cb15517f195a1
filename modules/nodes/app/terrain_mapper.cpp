// terrain_mapper: POINT_CLOUD and ROBOT_STATE in; TERRAIN (the mapped terrain), ELEVATION_MAP and
// STATUS out.
#include <iostream>

#include "rbcp/cli/cli.h"
#include "rbcp/mapping/terrain_map.h"
#include "rbcp/nodes/terrain_mapper_node.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/run_loop.h"

namespace {

using namespace rbcp;

struct Options {
  cli::CommonOptions common;
  std::string config_path;
  nodes::TerrainMapperNodeChannels channels;
};

void AddOptions(CLI::App& app, Options& o) {
  app.description(
      "Terrain mapping: depth clouds (POINT_CLOUD) placed with the robot's state (ROBOT_STATE) -> an elevation map "
      "and an occupancy octree around the robot -> the known terrain as a mesh (TERRAIN) and the grid "
      "(ELEVATION_MAP). Unknown cells are no terrain.");
  cli::AddCommonOptions(app, o.common);
  app.add_option("--config", o.config_path, "mapper parameters (default: CONFIG_DIR/mapper.yaml)");
  app.add_option("--terrain-channel", o.channels.terrain, "channel of the mapped terrain")->capture_default_str();
}

int Run(const Options& o) {
  const auto config =
      mapping::MapperConfig::LoadFile(o.config_path.empty() ? o.common.config_dir + "/mapper.yaml" : o.config_path);
  const RobotModel robot = RobotModel::LoadDefault(o.common.config_dir);
  auto lcm = transport::OpenLcm(o.common.lcm_url);
  nodes::TerrainMapperNode node(*lcm, config, robot, {}, o.channels);
  node.status().set_verbose(!o.common.quiet);
  std::cerr << "[terrain_mapper] listening: POINT_CLOUD, ROBOT_STATE -> " << o.channels.terrain
            << ", ELEVATION_MAP, STATUS\n";
  node.status().StartBackgroundHeartbeat(0.4, 60.0);
  return transport::RunLoop(*lcm, [&] { node.Step(); }, [&] { node.Heartbeat(); }, {1.0, 20, o.common.max_runtime_s});
}

}  // namespace

int main(int argc, char** argv) {
  return rbcp::cli::Main(rbcp::nodes::TerrainMapperNode::kProcessName, argc, argv, AddOptions, Run);
}
