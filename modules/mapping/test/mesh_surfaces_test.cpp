// The mapped terrain as the planners see it: the mesh of the elevation map, through affordance
// extraction with the shipped parameters, gives the contact surfaces of the true terrain.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "box_scene.h"
#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping {
namespace {

using test_scene::Box;
using test_scene::Camera;
using test_scene::Capture;
using test_scene::Scene;

const std::string kConfig = std::string(RBCP_SOURCE_DIR) + "/config";

std::vector<AffordanceSurface> Surfaces(const TerrainMap& map) {
  AffordanceExtractor extractor(AffordanceConfig::Load(YamlMap::LoadFile(kConfig + "/affordance.yaml")));
  return extractor.Extract(map.ToMesh());
}

/// The front depth camera of the simulator's defaults on a robot standing at the origin.
Camera FrontCamera() {
  Camera cam;
  cam.origin = {0.31, 0.0, 0.53};
  cam.pitch_rad = 0.72;
  cam.hfov_rad = 1.518;  // 87 degrees
  cam.vfov_rad = 1.012;  // 58 degrees
  cam.cols = 64;
  cam.rows = 40;
  cam.max_range_m = 3.5;
  return cam;
}

/// The largest surface's area, and the total.
std::pair<double, double> Areas(const std::vector<AffordanceSurface>& surfaces) {
  double largest = 0.0, total = 0.0;
  for (const auto& s : surfaces) {
    largest = std::max(largest, s.area);
    total += s.area;
  }
  return {largest, total};
}

TEST(MappedSurfaces, OneCaptureOfAFloorIsOneContactSurface) {
  const Scene scene{{}};
  TerrainMap map{MapperConfig::LoadFile(kConfig + "/mapper.yaml")};
  map.Recenter({0, 0});
  std::mt19937 rng(3);
  map.Integrate(Capture(scene, FrontCamera(), 0.01, rng));
  const auto surfaces = Surfaces(map);
  const auto [largest, total] = Areas(surfaces);
  // Single returns 1 cm off along their rays would break the floor into slivers; its plane is one
  // surface (minus the ragged far edge, cut into small convex pieces).
  EXPECT_GT(largest, 0.7 * total) << surfaces.size() << " surfaces";
  EXPECT_GT(largest, 1.0);
  for (const auto& s : surfaces) EXPECT_GT(s.normal.z(), std::cos(0.02)) << "level within about a degree";
}

TEST(MappedSurfaces, ABlocksTopIsAContactSurfaceAtItsHeight) {
  const Scene scene{{Box{{0.9, -0.2, 0.0}, {1.3, 0.2, 0.12}}}};
  TerrainMap map{MapperConfig::LoadFile(kConfig + "/mapper.yaml")};
  map.Recenter({0, 0});
  std::mt19937 rng(5);
  for (int i = 0; i < 3; ++i) map.Integrate(Capture(scene, FrontCamera(), 0.01, rng));
  const auto surfaces = Surfaces(map);
  // The top: convex pieces of one eroded region (its outline is not quite a square).
  double top_area = 0.0;
  for (const auto& s : surfaces) {
    if (s.vertices.front().z() < 0.06) continue;
    top_area += s.area;
    for (const Eigen::Vector3d& v : s.vertices) {
      EXPECT_NEAR(v.z(), 0.12, 0.01);
      EXPECT_GE(v.x(), 0.9 + 0.04 - 1e-9) << "eroded from the edge";
      EXPECT_LE(v.x(), 1.3 - 0.04 + 1e-9);
    }
  }
  // 0.4 m x 0.4 m eroded by 4 cm is 0.1 m^2; the returns of its edge cells mix top and ground.
  EXPECT_GT(top_area, 0.05);
}

}  // namespace
}  // namespace rbcp::mapping
