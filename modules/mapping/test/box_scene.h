#pragma once
/// A simulated depth camera for the mapping tests and benchmark: rays from a pinhole camera
/// against axis-aligned boxes standing on the ground plane z = 0, with Gaussian range noise.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "rbcp/core/triangle_mesh.h"
#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping::test_scene {

struct Box {
  Eigen::Vector3d lo;
  Eigen::Vector3d hi;
};

struct Scene {
  std::vector<Box> boxes;
  double ground_half_extent_m = 20.0;  ///< the ground is the square [-e, e]^2 at z = 0

  /// The true terrain: the ground as two triangles and every box as a closed box mesh.
  TriangleMesh Truth() const {
    const double e = ground_half_extent_m;
    TriangleMesh mesh;
    mesh.vertices = {{-e, -e, 0}, {e, -e, 0}, {e, e, 0}, {-e, e, 0}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    for (const Box& b : boxes) {
      TriangleMesh box = MakeBoxMesh(b.hi - b.lo);
      Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
      at.translation() = 0.5 * (b.lo + b.hi);
      box.Transform(at);
      mesh.Append(box);
    }
    return mesh;
  }

  /// The distance along the unit ray (o, d) to the first surface; infinity when it hits nothing.
  double Cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    double best = std::numeric_limits<double>::infinity();
    if (d.z() < 0) {
      const double t = -o.z() / d.z();
      const Eigen::Vector3d p = o + t * d;
      if (t > 0 && std::abs(p.x()) <= ground_half_extent_m && std::abs(p.y()) <= ground_half_extent_m) best = t;
    }
    for (const Box& b : boxes) {
      // Slabs: the ray's interval inside each pair of parallel faces.
      double t0 = 0.0, t1 = best;
      for (int k = 0; k < 3 && t0 <= t1; ++k) {
        if (std::abs(d[k]) < 1e-12) {
          if (o[k] < b.lo[k] || o[k] > b.hi[k]) t0 = t1 + 1;
          continue;
        }
        double a = (b.lo[k] - o[k]) / d[k], c = (b.hi[k] - o[k]) / d[k];
        if (a > c) std::swap(a, c);
        t0 = std::max(t0, a);
        t1 = std::min(t1, c);
      }
      if (t0 <= t1 && t0 > 0 && t0 < best) best = t0;
    }
    return best;
  }
};

/// A pinhole depth camera looking along yaw (about z) and pitch (down positive).
struct Camera {
  Eigen::Vector3d origin = Eigen::Vector3d(0, 0, 0.5);
  double yaw_rad = 0.0;
  double pitch_rad = 0.5;
  double hfov_rad = 1.0;
  double vfov_rad = 0.75;
  int cols = 64;
  int rows = 48;
  double max_range_m = 8.0;  ///< no return beyond this
};

/// One capture of `scene`: a return per ray that hits within the camera's range, its range
/// perturbed by N(0, sigma).
inline WorldCloud Capture(const Scene& scene, const Camera& cam, double sigma, std::mt19937& rng) {
  const Eigen::Vector3d forward(std::cos(cam.pitch_rad) * std::cos(cam.yaw_rad),
                                std::cos(cam.pitch_rad) * std::sin(cam.yaw_rad), -std::sin(cam.pitch_rad));
  const Eigen::Vector3d left(-std::sin(cam.yaw_rad), std::cos(cam.yaw_rad), 0.0);
  const Eigen::Vector3d up = forward.cross(left);
  std::normal_distribution<double> noise(0.0, sigma);
  WorldCloud cloud;
  cloud.origin = cam.origin;
  cloud.range_noise_std = sigma;
  cloud.points.reserve(static_cast<std::size_t>(cam.cols * cam.rows));
  for (int r = 0; r < cam.rows; ++r) {
    for (int c = 0; c < cam.cols; ++c) {
      const double u = (c + 0.5) / cam.cols - 0.5, v = 0.5 - (r + 0.5) / cam.rows;
      const Eigen::Vector3d d = (forward + 2 * u * std::tan(0.5 * cam.hfov_rad) * left +
                                 2 * v * std::tan(0.5 * cam.vfov_rad) * up).normalized();
      const double t = scene.Cast(cam.origin, d);
      if (!(t <= cam.max_range_m)) continue;
      const double measured = sigma > 0 ? t + noise(rng) : t;
      cloud.points.push_back(cam.origin + measured * d);
    }
  }
  return cloud;
}

/// A rubble-like field: `count` boxes of 0.2-0.5 m sides and 0.04-0.2 m heights, some stacked on
/// others, scattered over [x0, x1] x [y0, y1].
inline Scene Rubble(int count, double x0, double x1, double y0, double y1, std::mt19937& rng) {
  std::uniform_real_distribution<double> side(0.2, 0.5), height(0.04, 0.2), ux(x0, x1), uy(y0, y1);
  Scene scene;
  for (int i = 0; i < count; ++i) {
    const double sx = side(rng), sy = side(rng), cx = ux(rng), cy = uy(rng);
    // A box stands on the highest box below its centre, or on the ground.
    double base = 0.0;
    for (const Box& b : scene.boxes) {
      if (cx > b.lo.x() && cx < b.hi.x() && cy > b.lo.y() && cy < b.hi.y()) base = std::max(base, b.hi.z());
    }
    scene.boxes.push_back({{cx - 0.5 * sx, cy - 0.5 * sy, 0.0}, {cx + 0.5 * sx, cy + 0.5 * sy, base + height(rng)}});
  }
  return scene;
}

}  // namespace rbcp::mapping::test_scene
