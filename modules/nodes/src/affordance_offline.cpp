#include "rbcp/nodes/affordance_offline.h"

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "rbcp/scenario/scenario.h"

namespace rbcp::nodes {
namespace {
nlohmann::json Vec(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }
}  // namespace

AffordanceReport ExtractScenario(const std::string& scenario_path, const AffordanceConfig& config) {
  const Scenario scenario = LoadScenario(scenario_path);
  AffordanceExtractor extractor(config);
  AffordanceReport report;
  report.scenario = scenario.name;
  report.triangles = scenario.terrain_mesh.NumTriangles();
  const auto start = std::chrono::steady_clock::now();
  report.surfaces = extractor.Extract(scenario.terrain_mesh);
  report.extract_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return report;
}

nlohmann::json ToJson(const AffordanceReport& report) {
  nlohmann::json surfaces = nlohmann::json::array();
  for (const auto& s : report.surfaces) {
    nlohmann::json vertices = nlohmann::json::array();
    for (const auto& v : s.vertices) vertices.push_back(Vec(v));
    surfaces.push_back({{"vertices", vertices}, {"normal", Vec(s.normal)}, {"area", s.area}});
  }
  return {{"scenario", report.scenario},
          {"triangles", report.triangles},
          {"surfaces", surfaces},
          {"extract_ms", report.extract_ms}};
}

std::string Summary(const AffordanceReport& report) {
  double area = 0.0;
  for (const auto& s : report.surfaces) area += s.area;
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%s: %zu triangles -> %zu contact surfaces, %.3f m^2 in all, extracted in %.3f ms",
                report.scenario.c_str(), report.triangles, report.surfaces.size(), area, report.extract_ms);
  return buf;
}

}  // namespace rbcp::nodes
