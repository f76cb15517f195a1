// generate_roms: writes the four leg range-of-motion shapes (ROMs) of the robot as OBJ files.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "rbcp/robot/robot_model.h"
#include "rbcp/root_planner/rom.h"

int main(int argc, char** argv) {
  using namespace rbcp;
  CLI::App app{"Generate the leg range-of-motion shapes (convex hulls of sampled foot positions, base frame).\n"
               "Talks no LCM."};
  std::string config_dir = RBCP_DEFAULT_CONFIG_DIR;
  std::string params;
  std::string output;
  app.add_option("--config-dir", config_dir, "configuration folder holding robots/anymal_b.{urdf,yaml}")
      ->check(CLI::ExistingDirectory);
  app.add_option("--params", params, "generation parameters (default: CONFIG_DIR/robots/anymal_b_roms/rom_generation.yaml)");
  app.add_option("--output", output, "folder receiving LF.obj, RF.obj, LH.obj, RH.obj (default: the folder of --params)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help is 0; a bad argument is bad input
  }
  try {
    if (params.empty()) params = config_dir + "/robots/anymal_b_roms/rom_generation.yaml";
    if (output.empty()) output = params.substr(0, params.find_last_of('/') == std::string::npos ? 0 : params.find_last_of('/'));
    if (output.empty()) output = ".";
    const RobotModel robot = RobotModel::LoadDefault(config_dir);
    const RomGenerationConfig config = RomGenerationConfig::LoadFile(params);
    for (Leg leg : kAllLegs) {
      RomGenerationReport report;
      const ConvexPolytope rom = GenerateRom(robot, leg, config, &report);
      std::vector<std::string> header = {"Range of motion of the " + std::string(LegName(leg)) +
                                             " foot contact point, base frame [m]; written by generate_roms.",
                                         "Regenerate with generate_roms from the parameters below (rom_generation.yaml)."};
      for (const auto& line : config.Describe()) header.push_back(line);
      SaveObj(rom, RomPath(output, leg), header);
      std::printf("%s: %d samples kept, %d self-collisions; hull %d triangles %.4f m^3 -> %zu triangles %.4f m^3 "
                  "(%.1f %%), scaled %.2f -> %.4f m^3\n",
                  std::string(LegName(leg)).c_str(), report.accepted_samples, report.rejected_samples,
                  report.full_hull_triangles, report.full_hull_volume, rom.triangles.size(), report.simplified_volume,
                  100.0 * report.simplified_volume / report.full_hull_volume, config.scale, rom.Volume());
    }
  } catch (const std::exception& e) {
    std::cerr << "generate_roms: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
