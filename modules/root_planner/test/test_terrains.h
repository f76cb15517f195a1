#pragma once
// Hand-made terrains and contact surfaces for the root planner tests.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/triangle_mesh.h"

namespace rbcp::test {

inline const std::string kConfigDir = std::string(RBCP_SOURCE_DIR) + "/config";

/// A solid box from `lo` to `hi` (world frame).
inline TriangleMesh Box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh = MakeBoxMesh(hi - lo);
  mesh.Transform(Eigen::Isometry3d(Eigen::Translation3d(0.5 * (lo + hi))));
  return mesh;
}

/// The horizontal rectangle [x0, x1] x [y0, y1] at height z as a contact surface.
inline AffordanceSurface Rectangle(double x0, double x1, double y0, double y1, double z) {
  AffordanceSurface s;
  s.vertices = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  s.normal = Eigen::Vector3d::UnitZ();
  s.area = (x1 - x0) * (y1 - y0);
  return s;
}

/// Ground slabs (top at z = 0) between the given x intervals, y in [-1.5, 1.5], and their top
/// faces as surfaces.
struct Platforms {
  TriangleMesh terrain;
  std::vector<AffordanceSurface> surfaces;
};

inline Platforms MakePlatforms(const std::vector<std::pair<double, double>>& x_ranges) {
  Platforms p;
  for (const auto& [x0, x1] : x_ranges) {
    p.terrain.Append(Box({x0, -1.5, -0.5}, {x1, 1.5, 0.0}));
    p.surfaces.push_back(Rectangle(x0, x1, -1.5, 1.5, 0.0));
  }
  return p;
}

}  // namespace rbcp::test
