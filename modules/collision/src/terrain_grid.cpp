#include "terrain_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/core/error.h"

namespace rbcp::collision_detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinCell = 0.05;  // [m]
constexpr int kMaxCellsPerAxis = 1024;

// orient2d(a, b, p) evaluated with the corners in a canonical order, so that the value for the
// edge b->a is exactly the negation of the value for a->b. Shared edges then classify a point
// lying on them identically from both triangles.
double Orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const bool a_first = a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  const Eigen::Vector2d& u = a_first ? a : b;
  const Eigen::Vector2d& v = a_first ? b : a;
  const double w = (v.x() - u.x()) * (p.y() - u.y()) - (v.y() - u.y()) * (p.x() - u.x());
  return a_first ? w : -w;
}

// Top-left fill rule for a counter-clockwise triangle: a point exactly on an edge belongs to the
// triangle when the edge runs towards -y, or is horizontal and runs towards -x. Of two triangles
// sharing an edge (traversed in opposite directions) exactly one owns its points.
bool OwnsEdge(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return b.y() < a.y() || (b.y() == a.y() && b.x() < a.x());
}

bool Covers(const std::array<Eigen::Vector2d, 3>& t, const Eigen::Vector2d& p) {
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector2d& a = t[k];
    const Eigen::Vector2d& b = t[(k + 1) % 3];
    const double w = Orient(a, b, p);
    if (w < 0.0 || (w == 0.0 && !OwnsEdge(a, b))) return false;
  }
  return true;
}

}  // namespace

TerrainGrid::TerrainGrid(const TriangleMesh& mesh) {
  RBCP_CHECK(!mesh.Empty(), "terrain grid of an empty mesh");
  bounds_.lo = Eigen::Vector3d::Constant(kInf);
  bounds_.hi = Eigen::Vector3d::Constant(-kInf);
  for (const auto& t : mesh.triangles) {
    for (int k : t) {
      const Eigen::Vector3d& v = mesh.vertices[static_cast<std::size_t>(k)];
      bounds_.lo = bounds_.lo.cwiseMin(v);
      bounds_.hi = bounds_.hi.cwiseMax(v);
    }
  }
  const double ex = bounds_.hi.x() - bounds_.lo.x();
  const double ey = bounds_.hi.y() - bounds_.lo.y();
  cell_ = std::max({kMinCell, ex / kMaxCellsPerAxis, ey / kMaxCellsPerAxis});
  nx_ = std::max(1, static_cast<int>(std::ceil(ex / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(ey / cell_)));
  const std::size_t cells = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  max_z_.assign(cells, -kInf);
  std::vector<int> count(cells, 0);

  triangles_.reserve(mesh.NumTriangles());
  for (std::size_t i = 0; i < mesh.NumTriangles(); ++i) {
    GridTriangle t;
    t.corners = {mesh.Corner(i, 0), mesh.Corner(i, 1), mesh.Corner(i, 2)};
    t.bounds.lo = t.corners[0].cwiseMin(t.corners[1]).cwiseMin(t.corners[2]);
    t.bounds.hi = t.corners[0].cwiseMax(t.corners[1]).cwiseMax(t.corners[2]);
    const Eigen::Vector3d n = (t.corners[1] - t.corners[0]).cross(t.corners[2] - t.corners[0]);
    t.normal = n.normalized();
    t.offset = t.normal.dot(t.corners[0]);
    t.cells = {CellX(t.bounds.lo.x()), CellY(t.bounds.lo.y()), CellX(t.bounds.hi.x()), CellY(t.bounds.hi.y())};
    for (int iy = t.cells[1]; iy <= t.cells[3]; ++iy) {
      for (int ix = t.cells[0]; ix <= t.cells[2]; ++ix) {
        const std::size_t c = static_cast<std::size_t>(iy * nx_ + ix);
        max_z_[c] = std::max(max_z_[c], t.bounds.hi.z());
        ++count[c];
      }
    }
    t.xy = {t.corners[0].head<2>(), t.corners[1].head<2>(), t.corners[2].head<2>()};
    if (std::abs(n.z()) > 1e-12 * n.norm()) {  // vertical triangles are never crossed by a vertical ray
      t.ray_sign = n.z() > 0.0 ? 1 : -1;
      if (t.ray_sign < 0) std::swap(t.xy[1], t.xy[2]);
      t.z0 = t.corners[0].z();
      t.gx = -n.x() / n.z();
      t.gy = -n.y() / n.z();
    }
    triangles_.push_back(t);
  }

  cell_begin_.assign(cells + 1, 0);
  for (std::size_t c = 0; c < cells; ++c) cell_begin_[c + 1] = cell_begin_[c] + count[c];
  cell_triangles_.assign(static_cast<std::size_t>(cell_begin_[cells]), -1);
  std::vector<int> fill(cell_begin_.begin(), cell_begin_.end() - 1);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    const auto& cells_of = triangles_[i].cells;
    for (int iy = cells_of[1]; iy <= cells_of[3]; ++iy) {
      for (int ix = cells_of[0]; ix <= cells_of[2]; ++ix) {
        cell_triangles_[static_cast<std::size_t>(fill[static_cast<std::size_t>(iy * nx_ + ix)]++)] = static_cast<int>(i);
      }
    }
  }
}

int TerrainGrid::CellX(double x) const {
  const int i = static_cast<int>(std::floor((x - bounds_.lo.x()) / cell_));
  return std::clamp(i, 0, nx_ - 1);
}

int TerrainGrid::CellY(double y) const {
  const int i = static_cast<int>(std::floor((y - bounds_.lo.y()) / cell_));
  return std::clamp(i, 0, ny_ - 1);
}

double TerrainGrid::MaxHeightOver(const Aabb& box) const {
  if (box.hi.x() < bounds_.lo.x() || box.lo.x() > bounds_.hi.x() || box.hi.y() < bounds_.lo.y() ||
      box.lo.y() > bounds_.hi.y()) {
    return -kInf;
  }
  const int ix0 = CellX(box.lo.x()), ix1 = CellX(box.hi.x()), iy0 = CellY(box.lo.y()), iy1 = CellY(box.hi.y());
  double m = -kInf;
  for (int iy = iy0; iy <= iy1; ++iy) {
    const double* row = max_z_.data() + iy * nx_;
    for (int ix = ix0; ix <= ix1; ++ix) m = std::max(m, row[ix]);
  }
  return m;
}

bool TerrainGrid::Inside(const Eigen::Vector3d& p, double* depth_below_surface) const {
  if (!(p.x() >= bounds_.lo.x() && p.x() <= bounds_.hi.x() && p.y() >= bounds_.lo.y() && p.y() <= bounds_.hi.y() &&
        p.z() < bounds_.hi.z())) {
    return false;
  }
  const std::size_t c = static_cast<std::size_t>(CellY(p.y()) * nx_ + CellX(p.x()));
  const Eigen::Vector2d q = p.head<2>();
  int winding = 0;
  double nearest_up = kInf;
  for (int k = cell_begin_[c]; k < cell_begin_[c + 1]; ++k) {
    const GridTriangle& t = triangles_[static_cast<std::size_t>(cell_triangles_[static_cast<std::size_t>(k)])];
    if (t.ray_sign == 0 || !(t.bounds.hi.z() > p.z()) || !Covers(t.xy, q)) continue;
    const double z = t.z0 + t.gx * (q.x() - t.xy[0].x()) + t.gy * (q.y() - t.xy[0].y());
    if (!(z > p.z())) continue;
    winding += t.ray_sign;
    if (t.ray_sign > 0) nearest_up = std::min(nearest_up, z - p.z());
  }
  const bool inside = winding > 0;
  if (inside && depth_below_surface != nullptr) *depth_below_surface = nearest_up;
  return inside;
}

}  // namespace rbcp::collision_detail
