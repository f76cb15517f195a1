// Writes (or, with --check, compares) config/scenarios/<name>.yaml for the four benchmark terrains.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "rbcp/scenario/benchmark_terrains.h"

int main(int argc, char** argv) {
  CLI::App app{"Generate the benchmark scenario files (flat_ground, slalom_debris, plinth, darpa_rubble). Talks no LCM."};
  std::string out_dir = "config/scenarios";
  bool check = false;
  app.add_option("--out", out_dir, "Folder of the scenario files")->capture_default_str();
  app.add_flag("--check", check, "Compare with the files instead of writing them; exit 1 on any difference");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help is 0; a bad argument is bad input
  }

  int problems = 0;
  if (!check) std::filesystem::create_directories(out_dir);
  for (const rbcp::BenchmarkScenario& b : rbcp::MakeBenchmarkScenarios()) {
    const std::string path = (std::filesystem::path(out_dir) / (b.scenario.name + ".yaml")).string();
    const std::string text = rbcp::BenchmarkScenarioText(b);
    if (check) {
      std::ifstream in(path, std::ios::binary);
      std::ostringstream current;
      if (in) current << in.rdbuf();
      const char* verdict = !in ? "missing" : current.str() == text ? "up to date" : "differs from the generator";
      std::cout << path << ": " << verdict << "\n";
      problems += (in && current.str() == text) ? 0 : 1;
    } else {
      const bool written = static_cast<bool>(std::ofstream(path, std::ios::binary) << text);
      std::cout << (written ? "wrote " : "cannot write ") << path << "\n";
      problems += written ? 0 : 1;
    }
  }
  return problems == 0 ? 0 : 1;
}
