// Speed of the terrain mapper on the simulated depth camera's clouds (test/box_scene.h): one
// 3072-point cloud integrated into the map, the map meshed, the map judged against a large mesh.
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "box_scene.h"
#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping {
namespace {

MapperConfig DefaultConfig() { return MapperConfig::LoadFile(std::string(RBCP_SOURCE_DIR) + "/config/mapper.yaml"); }

/// Ten clouds of a rubble field, taken from where the robot stands (64 x 48 rays each).
std::vector<WorldCloud> RubbleClouds(test_scene::Scene* scene) {
  std::mt19937 rng(1);
  *scene = test_scene::Rubble(14, 0.6, 2.2, -0.9, 0.9, rng);
  std::vector<WorldCloud> clouds;
  for (int i = 0; i < 10; ++i) {
    test_scene::Camera cam;
    cam.yaw_rad = 0.1 * (i - 5);
    clouds.push_back(test_scene::Capture(*scene, cam, 0.01, rng));
  }
  return clouds;
}

void BM_IntegrateCloud(benchmark::State& state) {
  test_scene::Scene scene;
  const std::vector<WorldCloud> clouds = RubbleClouds(&scene);
  TerrainMap map(DefaultConfig());
  map.Recenter({0, 0});
  std::size_t i = 0;
  for (auto _ : state) {
    const IntegrateReport r = map.Integrate(clouds[i++ % clouds.size()]);
    benchmark::DoNotOptimize(r);
  }
  state.counters["points"] = static_cast<double>(clouds[0].points.size());
  state.counters["octree_nodes"] = static_cast<double>(map.OccupancyNodes());
  state.counters["memory_MB"] = static_cast<double>(map.MemoryBytes()) / 1e6;
}
BENCHMARK(BM_IntegrateCloud)->Unit(benchmark::kMillisecond);

void BM_ToMesh(benchmark::State& state) {
  test_scene::Scene scene;
  const std::vector<WorldCloud> clouds = RubbleClouds(&scene);
  TerrainMap map(DefaultConfig());
  map.Recenter({0, 0});
  for (const WorldCloud& c : clouds) map.Integrate(c);
  std::size_t triangles = 0;
  for (auto _ : state) {
    const TriangleMesh mesh = map.ToMesh();
    triangles = mesh.NumTriangles();
    benchmark::DoNotOptimize(triangles);
  }
  state.counters["known_cells"] = static_cast<double>(map.elevation().KnownCells());
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_ToMesh)->Unit(benchmark::kMillisecond);

/// The whole 8 m window known, judged against a 100k-triangle truth (a fine grid of the ground).
void BM_MeasureHeightError(benchmark::State& state) {
  ElevationMap map(DefaultConfig().elevation);
  map.Recenter({0, 0});
  for (int iy = 0; iy < map.num_y(); ++iy) {
    for (int ix = 0; ix < map.num_x(); ++ix) {
      const Eigen::Vector2d c = map.CellCentre(ix, iy);
      map.Fuse({c.x(), c.y(), 0.0}, 1e-4);
    }
  }
  TriangleMesh truth;
  const int n = 224;  // 2 x 223^2 = 99458 triangles over 10 m
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) truth.vertices.emplace_back(-5.0 + 10.0 * i / (n - 1), -5.0 + 10.0 * j / (n - 1), 0.0);
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      truth.triangles.push_back({a, a + 1, a + n + 1});
      truth.triangles.push_back({a, a + n + 1, a + n});
    }
  }
  for (auto _ : state) benchmark::DoNotOptimize(MeasureHeightError(map, truth));
  state.counters["cells"] = static_cast<double>(map.KnownCells());
  state.counters["triangles"] = static_cast<double>(truth.NumTriangles());
}
BENCHMARK(BM_MeasureHeightError)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rbcp::mapping

BENCHMARK_MAIN();
