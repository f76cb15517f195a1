// scenario_publisher: publishes a scenario's terrain on TERRAIN (standing in for the simulator's
// world publication), waits for the affordance process to answer, and prints what came back.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "rbcp/nodes/process.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/run_loop.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"

int main(int argc, char** argv) {
  using namespace rbcp;
  CLI::App app{"Publishes a scenario's terrain on TERRAIN and reports the AFFORDANCES answer."};
  nodes::CommonOptions common;
  nodes::AddCommonOptions(app, common);
  std::string scenario_path;
  double timeout_s = 10.0, period_s = 0.5;
  app.add_option("--scenario", scenario_path, "scenario YAML")->required()->check(CLI::ExistingFile);
  app.add_option("--timeout", timeout_s, "give up after this many seconds without an answer")->capture_default_str();
  app.add_option("--period", period_s, "republish the terrain this often until answered [s]")->capture_default_str();
  return nodes::GuardedMain("scenario_publisher", app, argc, argv, [&]() -> int {
    const Scenario scenario = LoadScenario(scenario_path);
    auto lcm = transport::OpenLcm(common.lcm_url);
    transport::LatestMessage<rbcp_msgs::affordance_set_t> affordances(*lcm, channels::kAffordances);
    transport::LatestMessage<rbcp_msgs::process_status_t> status(*lcm, channels::kStatus);
    transport::InstallStopHandlers();
    const auto start = std::chrono::steady_clock::now();
    int64_t utime = 0;
    double extract_ms = -1.0;  // from the extractor's OK status, published right after AFFORDANCES
    for (auto next = start; !transport::StopRequested();) {
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - start).count() > timeout_s) {
        std::cerr << "scenario_publisher: no AFFORDANCES within " << timeout_s
                  << " s: is affordance_extractor running on this LCM URL?\n";
        return 1;
      }
      if (now >= next) {
        const auto msg = transport::ToTerrainMsg(scenario.terrain_mesh, utime, scenario.name);
        lcm->publish(channels::kTerrain, &msg);
        utime += static_cast<int64_t>(period_s * 1e6);
        next = now + std::chrono::milliseconds(static_cast<int>(period_s * 1000));
      }
      lcm->handleTimeout(20);
      auto s = status.Take();
      if (s && s->process == "affordance_extractor" && s->state == rbcp_msgs::process_status_t::OK) {
        extract_ms = s->compute_ms;
      }
      if (s && s->process == "affordance_extractor" && s->state == rbcp_msgs::process_status_t::FAILED) {
        std::cerr << "scenario_publisher: " << s->process << " failed: " << s->reason << "\n";
        return 1;
      }
      if (auto a = affordances.Take()) {
        for (int i = 0; i < 10 && extract_ms < 0.0; ++i) {
          lcm->handleTimeout(20);
          const auto& st = status.Latest();
          if (st && st->process == "affordance_extractor" && st->state == rbcp_msgs::process_status_t::OK) {
            extract_ms = st->compute_ms;
          }
        }
        const auto surfaces = transport::FromAffordanceMsg(*a);
        double area = 0.0;
        for (const auto& s : surfaces) area += s.area;
        std::cout << "scenario " << scenario.name << ": " << scenario.terrain_mesh.NumTriangles()
                  << " terrain triangles published on TERRAIN\n"
                  << "affordance_extractor: " << surfaces.size() << " contact surfaces (" << area
                  << " m^2) on AFFORDANCES";
        if (extract_ms >= 0.0) std::cout << ", extracted in " << extract_ms << " ms";
        std::cout << "\n";
        for (std::size_t i = 0; i < surfaces.size(); ++i) {
          const auto& s = surfaces[i];
          Eigen::Vector3d c = Eigen::Vector3d::Zero();
          for (const auto& v : s.vertices) c += v / static_cast<double>(s.vertices.size());
          std::printf("  surface %2zu: %zu vertices, area %.4f m^2, centre (%.3f, %.3f, %.3f), slope %.1f deg\n", i,
                      s.vertices.size(), s.area, c.x(), c.y(), c.z(), std::acos(std::min(1.0, s.normal.z())) * 180.0 / M_PI);
        }
        return 0;
      }
    }
    return 1;
  });
}
