// Speed of affordance extraction on synthetic terrains and, when the scenario loader is part of
// the build, on the committed benchmark scenarios (config/scenarios/*.yaml).
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/core/pose.h"
#include "rbcp/core/yaml_reader.h"
#ifdef RBCP_HAVE_SCENARIO
#include "rbcp/scenario/scenario.h"
#endif

namespace rbcp {
namespace {

AffordanceConfig DefaultConfig() {
  return AffordanceConfig::LoadFile(std::string(RBCP_SOURCE_DIR) + "/config/affordance.yaml");
}

TriangleMesh Box(const Eigen::Vector3d& size, const Eigen::Vector3d& centre,
                 const Eigen::Vector3d& rpy = Eigen::Vector3d::Zero()) {
  TriangleMesh m = MakeBoxMesh(size);
  m.Transform(PoseFromRpy(centre, rpy));
  return m;
}

/// The reference's flat ground: one 12.51 x 5.89 x 0.5 m box, top at z = 0 (12 triangles).
TriangleMesh FlatFloor() { return Box({12.51, 5.89, 0.5}, {0, 0, -0.25}); }

/// A DARPA-rubble-like field of 31 boxes (372 triangles): two floors, 16 cinder blocks tilted
/// 15 degrees in alternating directions on 8 sunk supports, a central plank and 4 side steps.
TriangleMesh Rubble() {
  const double deg = M_PI / 180.0;
  TriangleMesh m = Box({4.0, 1.43, 0.5}, {-2.41, -0.045, -0.25});
  m.Append(Box({4.0, 1.43, 0.5}, {2.84, -0.045, -0.25}));
  const double column_x[4] = {-0.39, -0.08, 0.53, 0.85};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const double tilt = 15 * deg * (((i + j) % 2) ? 1.0 : -1.0);
      const Eigen::Vector3d rpy = (j % 2) ? Eigen::Vector3d(tilt, 0, 0) : Eigen::Vector3d(0, tilt, 0);
      m.Append(Box({0.30, 0.21, 0.15}, {column_x[i], -0.46 + 0.277 * j, 0.125 + 0.01 * ((i + 2 * j) % 4)}, rpy));
    }
  }
  for (int k = 0; k < 8; ++k) m.Append(Box({0.25, 0.4, 0.06}, {column_x[k % 4], k < 4 ? -0.3 : 0.25, 0.03}));
  m.Append(Box({0.30, 0.77, 0.342}, {0.225, -0.05, 0.171}));
  m.Append(Box({0.30, 0.30, 0.10}, {0.225, -0.59, 0.05}));
  m.Append(Box({0.30, 0.30, 0.20}, {0.525, -0.59, 0.10}));
  m.Append(Box({0.30, 0.30, 0.10}, {0.225, 0.51, 0.05}));
  m.Append(Box({0.30, 0.30, 0.20}, {0.525, 0.51, 0.10}));
  return m;
}

/// Non-convex floors, eroded on the general path: an L-shaped floor of 6 triangles and a square
/// frame of 16 triangles around a hole.
TriangleMesh NonConvex() {
  TriangleMesh m;
  const auto cells = [&m](const std::vector<std::pair<int, int>>& list, double size, const Eigen::Vector3d& origin) {
    for (const auto& [i, j] : list) {
      const int base = static_cast<int>(m.vertices.size());
      for (const auto& [di, dj] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
        m.vertices.push_back(origin + Eigen::Vector3d((i + di) * size, (j + dj) * size, 0.0));
      }
      m.triangles.push_back({base, base + 1, base + 2});
      m.triangles.push_back({base, base + 2, base + 3});
    }
  };
  cells({{0, 0}, {1, 0}, {0, 1}}, 0.5, {0, 0, 0});
  cells({{0, 0}, {1, 0}, {2, 0}, {0, 1}, {2, 1}, {0, 2}, {1, 2}, {2, 2}}, 0.4, {2, 0, 0.2});
  return m;
}

void Run(benchmark::State& state, const TriangleMesh& mesh) {
  AffordanceExtractor extractor(DefaultConfig());
  std::size_t surfaces = 0;
  for (auto _ : state) {
    auto out = extractor.Extract(mesh);
    surfaces = out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["triangles"] = static_cast<double>(mesh.NumTriangles());
  state.counters["surfaces"] = static_cast<double>(surfaces);
  state.counters["regions"] = extractor.stats().planar_regions;
}

void BM_ExtractFlatFloor(benchmark::State& state) { Run(state, FlatFloor()); }
void BM_ExtractRubble(benchmark::State& state) { Run(state, Rubble()); }
void BM_ExtractNonConvex(benchmark::State& state) { Run(state, NonConvex()); }

/// The same rubble extracted into a reused output vector: no allocation once warm.
void BM_ExtractRubbleReusingOutput(benchmark::State& state) {
  const TriangleMesh mesh = Rubble();
  AffordanceExtractor extractor(DefaultConfig());
  std::vector<AffordanceSurface> out;
  for (auto _ : state) {
    extractor.Extract(mesh, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["surfaces"] = static_cast<double>(out.size());
}

BENCHMARK(BM_ExtractFlatFloor)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ExtractRubble)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ExtractRubbleReusingOutput)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ExtractNonConvex)->Unit(benchmark::kMicrosecond);

#ifdef RBCP_HAVE_SCENARIO
void BM_ExtractScenario(benchmark::State& state, const std::string& name) {
  const std::string path = std::string(RBCP_SOURCE_DIR) + "/config/scenarios/" + name + ".yaml";
  TriangleMesh mesh;
  try {
    mesh = LoadScenario(path).terrain_mesh;
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  Run(state, mesh);
}

BENCHMARK_CAPTURE(BM_ExtractScenario, flat_ground, std::string("flat_ground"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ExtractScenario, slalom_debris, std::string("slalom_debris"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ExtractScenario, plinth, std::string("plinth"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ExtractScenario, darpa_rubble, std::string("darpa_rubble"))->Unit(benchmark::kMicrosecond);
#endif

}  // namespace
}  // namespace rbcp

BENCHMARK_MAIN();
