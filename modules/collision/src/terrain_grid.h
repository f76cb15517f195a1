#pragma once
// A uniform xy grid over a terrain mesh, the broad phase of the terrain collision queries. Per
// cell: an upper bound of the terrain height (to skip shapes clearly above the terrain) and the
// triangles whose xy bounds overlap the cell. The non-vertical triangles also answer the
// vertical-ray winding number that decides whether a point is inside the terrain solid.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "rbcp/core/triangle_mesh.h"

namespace rbcp::collision_detail {

/// World-frame axis-aligned box.
struct Aabb {
  Eigen::Vector3d lo;
  Eigen::Vector3d hi;
  bool Overlaps(const Aabb& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
  bool Contains(const Aabb& o) const { return (lo.array() <= o.lo.array()).all() && (o.hi.array() <= hi.array()).all(); }
};

/// One terrain triangle with what the queries need precomputed.
struct GridTriangle {
  std::array<Eigen::Vector3d, 3> corners;  // as in the mesh
  Aabb bounds;
  Eigen::Vector3d normal;  // unit, outward
  double offset = 0.0;     // normal . x = offset on the plane
  std::array<int, 4> cells{};  // ix0, iy0, ix1, iy1: the grid cells under the triangle
  // Vertical-ray data: corners in counter-clockwise order seen from above and the plane
  // z = z0 + gx (x - x0) + gy (y - y0) through corner 0. ray_sign is +1 for an upward-facing
  // triangle (a ray from below leaves the solid through it), -1 downward, 0 vertical.
  std::array<Eigen::Vector2d, 3> xy;
  double z0 = 0.0, gx = 0.0, gy = 0.0;
  int ray_sign = 0;
};

class TerrainGrid {
 public:
  /// `mesh` must be valid (ValidateMesh).
  explicit TerrainGrid(const TriangleMesh& mesh);

  const Aabb& Bounds() const { return bounds_; }

  /// An upper bound of the terrain height over the xy rectangle of `box`; -infinity when no
  /// triangle lies over it.
  double MaxHeightOver(const Aabb& box) const;

  /// Calls visit(triangle) once for every triangle whose bounds overlap `box`, in a fixed order,
  /// until visit returns true; returns whether it did.
  template <typename Visit>
  bool AnyTriangleNear(const Aabb& box, Visit&& visit) const;

  /// Winding number of the upward vertical ray from p: > 0 inside the terrain solid. When
  /// `depth_below_surface` is given and the point is inside, it receives the vertical distance to
  /// the nearest upward-facing triangle above p.
  bool Inside(const Eigen::Vector3d& p, double* depth_below_surface = nullptr) const;

 private:
  int CellX(double x) const;
  int CellY(double y) const;

  Aabb bounds_;
  double cell_ = 0.05;  // [m]
  int nx_ = 1;
  int ny_ = 1;
  std::vector<GridTriangle> triangles_;
  std::vector<double> max_z_;        // per cell, row-major (iy * nx + ix)
  std::vector<int> cell_begin_;      // offsets into cell_triangles_, size nx * ny + 1
  std::vector<int> cell_triangles_;  // indices into triangles_
};

template <typename Visit>
inline bool TerrainGrid::AnyTriangleNear(const Aabb& box, Visit&& visit) const {
  if (!box.Overlaps(bounds_)) return false;
  const int qx0 = CellX(box.lo.x()), qx1 = CellX(box.hi.x()), qy0 = CellY(box.lo.y()), qy1 = CellY(box.hi.y());
  for (int iy = qy0; iy <= qy1; ++iy) {
    for (int ix = qx0; ix <= qx1; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy * nx_ + ix);
      for (int k = cell_begin_[c]; k < cell_begin_[c + 1]; ++k) {
        const GridTriangle& t = triangles_[static_cast<std::size_t>(cell_triangles_[static_cast<std::size_t>(k)])];
        // A triangle spanning several queried cells is visited in the first of them only.
        if (ix != std::max(qx0, t.cells[0]) || iy != std::max(qy0, t.cells[1])) continue;
        if (!t.bounds.Overlaps(box)) continue;
        if (visit(t)) return true;
      }
    }
  }
  return false;
}

}  // namespace rbcp::collision_detail
