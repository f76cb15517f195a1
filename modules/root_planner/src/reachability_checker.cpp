#include "rbcp/root_planner/reachability_checker.h"

#include <fcl/geometry/shape/convex.h>
#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

std::shared_ptr<fcl::Convexd> MakeConvex(const std::vector<Eigen::Vector3d>& vertices,
                                         const std::vector<std::vector<int>>& faces) {
  auto v = std::make_shared<std::vector<fcl::Vector3d>>(vertices.begin(), vertices.end());
  auto f = std::make_shared<std::vector<int>>();
  for (const auto& face : faces) {
    f->push_back(static_cast<int>(face.size()));
    f->insert(f->end(), face.begin(), face.end());
  }
  auto convex = std::make_shared<fcl::Convexd>(v, static_cast<int>(faces.size()), f);
  convex->computeLocalAABB();
  return convex;
}

std::shared_ptr<fcl::Convexd> MakeConvex(const ConvexPolytope& poly) {
  std::vector<std::vector<int>> faces;
  faces.reserve(poly.triangles.size());
  for (const auto& t : poly.triangles) faces.push_back({t[0], t[1], t[2]});
  return MakeConvex(poly.vertices, faces);
}

// Axis-aligned box (centre, half extents) of a shape's local box moved by (R, p).
struct Aabb {
  Eigen::Vector3d lo;
  Eigen::Vector3d hi;
  bool Overlaps(const Aabb& o) const { return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all(); }
};

Aabb Bounds(const std::vector<Eigen::Vector3d>& points) {
  Aabb box{Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()),
           Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity())};
  for (const auto& p : points) {
    box.lo = box.lo.cwiseMin(p);
    box.hi = box.hi.cwiseMax(p);
  }
  return box;
}

Aabb Moved(const Aabb& local, const Eigen::Matrix3d& R, const Eigen::Vector3d& p) {
  const Eigen::Vector3d center = R * (0.5 * (local.lo + local.hi)) + p;
  const Eigen::Vector3d half = R.cwiseAbs() * (0.5 * (local.hi - local.lo));
  return {center - half, center + half};
}

// The xy bounds of a convex polytope's cross-sections: over each of `bins` horizontal slabs of
// equal height between its lowest and highest point, the xy box of the part of it inside the slab
// (exact: that part's corners are the polytope's corners inside the slab and its edges' crossings
// of the slab's planes). A cheap and exact-conservative reject before a GJK test: a shape whose xy
// box, over the heights it spans, misses the slabs' boxes cannot touch the polytope.
class SlabBounds {
 public:
  SlabBounds() = default;
  SlabBounds(const ConvexPolytope& poly, int bins) : bins_(bins) {
    const auto [lo, hi] = poly.Bounds();
    z0_ = lo.z();
    dz_ = std::max(hi.z() - lo.z(), 1e-9) / bins;
    lo_.assign(static_cast<std::size_t>(bins), Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()));
    hi_.assign(static_cast<std::size_t>(bins), Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity()));
    for (const auto& t : poly.triangles) {
      for (int k = 0; k < 3; ++k) {
        AddSegment(poly.vertices[static_cast<std::size_t>(t[k])], poly.vertices[static_cast<std::size_t>(t[(k + 1) % 3])]);
      }
    }
  }
  /// False when nothing of the polytope within heights [z_lo, z_hi] lies in the xy box [lo, hi].
  bool MayOverlap(double z_lo, double z_hi, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const {
    const int first = std::max(0, Bin(z_lo)), last = std::min(bins_ - 1, Bin(z_hi));
    for (int b = first; b <= last; ++b) {
      const std::size_t i = static_cast<std::size_t>(b);
      if ((lo.array() <= hi_[i].array()).all() && (lo_[i].array() <= hi.array()).all()) return true;
    }
    return false;
  }

 private:
  int Bin(double z) const { return static_cast<int>(std::floor((z - z0_) / dz_)); }
  // Adds the part of segment ab within each slab it crosses (its ends clipped to the slab).
  void AddSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double za = a.z(), zb = b.z();
    const int first = std::clamp(Bin(std::min(za, zb)), 0, bins_ - 1);
    const int last = std::clamp(Bin(std::max(za, zb)), 0, bins_ - 1);
    for (int k = first; k <= last; ++k) {
      const double s0 = z0_ + k * dz_, s1 = s0 + dz_;
      double t0 = 0.0, t1 = 1.0;
      if (std::abs(zb - za) > 1e-15) {
        const double ta = (s0 - za) / (zb - za), tb = (s1 - za) / (zb - za);
        t0 = std::max(0.0, std::min(ta, tb));
        t1 = std::min(1.0, std::max(ta, tb));
        if (t0 > t1) continue;
      }
      const std::size_t i = static_cast<std::size_t>(k);
      for (double t : {t0, t1}) {
        const Eigen::Vector2d q = (a + t * (b - a)).head<2>();
        lo_[i] = lo_[i].cwiseMin(q);
        hi_[i] = hi_[i].cwiseMax(q);
      }
    }
  }
  int bins_ = 0;
  double z0_ = 0.0, dz_ = 1.0;
  std::vector<Eigen::Vector2d> lo_, hi_;
};

Eigen::Matrix3d YawRotation(double yaw) { return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

}  // namespace

bool ReachabilityReport::Valid() const {
  if (trunk_collision) return false;
  return std::all_of(leg_surface.begin(), leg_surface.end(), [](int s) { return s >= 0; });
}

std::string ReachabilityReport::Reason() const {
  std::ostringstream os;
  if (trunk_collision) os << "trunk collides with the terrain";
  std::string legs;
  for (Leg leg : kAllLegs) {
    if (!LegInReach(leg)) legs += (legs.empty() ? "" : ", ") + std::string(LegName(leg));
  }
  if (!legs.empty()) os << (trunk_collision ? "; " : "") << "no contact surface in reach of " << legs;
  return os.str();
}

struct ReachabilityChecker::Impl {
  struct Surface {
    std::shared_ptr<fcl::Convexd> geometry;
    std::unique_ptr<fcl::CollisionObjectd> object;
    Aabb box;
    std::vector<Eigen::Vector3d> corners;  ///< the prism's
  };
  struct Rom {
    std::shared_ptr<fcl::Convexd> geometry;
    std::unique_ptr<fcl::CollisionObjectd> object;
    Aabb local_box;
    SlabBounds slabs;  ///< in the ROM's (base) frame
  };
  // Slabs of a ROM's cross-section bounds: ~1.5 cm each over a leg's ~0.5 m reach.
  static constexpr int kRomSlabs = 32;

  Aabb terrain_box;
  std::optional<PolytopeTriangleTest> trunk;
  Aabb trunk_local_box;
  std::array<Rom, kNumLegs> roms;
  std::vector<Surface> surfaces;
  std::array<int, kNumLegs> last_surface{{-1, -1, -1, -1}};
  long queries = 0;

  // Vertical-ray lookup of the terrain triangles: non-vertical triangles by xy grid cell.
  static constexpr double kMinCell = 0.1;           // [m]
  static constexpr double kMaxGridEntries = 1.0e6;  // (triangle, cell) pairs per grid
  double cell = kMinCell;
  std::vector<std::array<Eigen::Vector3d, 3>> ray_triangles;
  std::vector<double> ray_normal_z;
  std::unordered_map<std::uint64_t, std::vector<int>> grid;
  // Every terrain triangle with its bounding box, listed by xy grid cell: the trunk is tested
  // (separating axes) only against triangles whose boxes overlap its own.
  std::vector<Aabb> triangle_boxes;
  std::vector<std::array<Eigen::Vector3d, 3>> triangles;
  struct BoxCell {
    std::vector<int> triangles;
    double z_max = -std::numeric_limits<double>::infinity();  ///< highest point of its triangles
  };
  std::unordered_map<std::uint64_t, BoxCell> box_grid;
  std::vector<long> triangle_stamp;  // last query that tested each triangle
  long stamp = 0;

  static std::uint64_t Key(long ix, long iy) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)) << 32) | static_cast<std::uint32_t>(iy);
  }
  long CellIndex(double x) const { return static_cast<long>(std::floor(x / cell)); }

  /// Grid cells (listed, summed over the triangles) the xy bounds of every triangle cover with
  /// cells of `size`.
  static double Entries(const std::vector<Aabb>& boxes, double size) {
    double entries = 0.0;
    for (const Aabb& b : boxes) {
      const double nx = std::floor(b.hi.x() / size) - std::floor(b.lo.x() / size) + 1.0;
      const double ny = std::floor(b.hi.y() / size) - std::floor(b.lo.y() / size) + 1.0;
      entries += nx * ny;
    }
    return entries;
  }

  /// The cell size: kMinCell, doubled until the grids list at most kMaxGridEntries triangles in
  /// all (or at most 4 per triangle, with cells as large as the terrain), so that their memory
  /// grows with the number of triangles and not with the terrain's area.
  void ChooseCell(const TriangleMesh& mesh) {
    std::vector<Aabb> boxes;
    boxes.reserve(mesh.NumTriangles());
    for (std::size_t t = 0; t < mesh.NumTriangles(); ++t) boxes.push_back(Bounds({mesh.Corner(t, 0), mesh.Corner(t, 1), mesh.Corner(t, 2)}));
    const Eigen::Vector3d extent = terrain_box.hi - terrain_box.lo;
    const double largest = std::max({extent.x(), extent.y(), kMinCell});
    cell = kMinCell;
    while (cell < largest && Entries(boxes, cell) > kMaxGridEntries) cell *= 2.0;
  }

  void BuildBoxGrid(const TriangleMesh& mesh) {
    for (std::size_t t = 0; t < mesh.NumTriangles(); ++t) {
      const std::vector<Eigen::Vector3d> corners = {mesh.Corner(t, 0), mesh.Corner(t, 1), mesh.Corner(t, 2)};
      const Aabb box = Bounds(corners);
      const int index = static_cast<int>(triangle_boxes.size());
      triangle_boxes.push_back(box);
      triangles.push_back({corners[0], corners[1], corners[2]});
      for (long ix = CellIndex(box.lo.x()); ix <= CellIndex(box.hi.x()); ++ix) {
        for (long iy = CellIndex(box.lo.y()); iy <= CellIndex(box.hi.y()); ++iy) {
          BoxCell& c = box_grid[Key(ix, iy)];
          c.triangles.push_back(index);
          c.z_max = std::max(c.z_max, box.hi.z());
        }
      }
    }
    triangle_stamp.assign(triangle_boxes.size(), -1);
  }

  // Exact test of the trunk placed at (R, p) against the terrain triangles whose boxes overlap
  // `box`, its bounds.
  bool TrunkTouchesTriangles(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, const Aabb& box) {
    const Eigen::Matrix3d Rt = R.transpose();
    ++stamp;
    for (long ix = CellIndex(box.lo.x()); ix <= CellIndex(box.hi.x()); ++ix) {
      for (long iy = CellIndex(box.lo.y()); iy <= CellIndex(box.hi.y()); ++iy) {
        const auto it = box_grid.find(Key(ix, iy));
        // A cell whose triangles all lie below the trunk (the floor under it) has none to test.
        if (it == box_grid.end() || it->second.z_max < box.lo.z()) continue;
        for (int index : it->second.triangles) {
          const std::size_t i = static_cast<std::size_t>(index);
          if (triangle_stamp[i] == stamp) continue;
          triangle_stamp[i] = stamp;
          if (!triangle_boxes[i].Overlaps(box)) continue;
          const auto& t = triangles[i];
          if (trunk->Overlaps(Rt * (t[0] - p), Rt * (t[1] - p), Rt * (t[2] - p))) return true;
        }
      }
    }
    return false;
  }

  void BuildRayGrid(const TriangleMesh& mesh) {
    for (std::size_t t = 0; t < mesh.NumTriangles(); ++t) {
      const Eigen::Vector3d n = mesh.AreaNormal(t);
      const double norm = n.norm();
      if (norm <= 0.0 || std::abs(n.z()) < 1e-9 * norm) continue;
      const int index = static_cast<int>(ray_triangles.size());
      ray_triangles.push_back({mesh.Corner(t, 0), mesh.Corner(t, 1), mesh.Corner(t, 2)});
      ray_normal_z.push_back(n.z() / norm);
      double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
      for (const auto& c : ray_triangles.back()) {
        x0 = std::min(x0, c.x());
        x1 = std::max(x1, c.x());
        y0 = std::min(y0, c.y());
        y1 = std::max(y1, c.y());
      }
      for (long ix = CellIndex(x0); ix <= CellIndex(x1); ++ix) {
        for (long iy = CellIndex(y0); iy <= CellIndex(y1); ++iy) grid[Key(ix, iy)].push_back(index);
      }
    }
  }

  // True when p lies inside a solid of the terrain: the nearest surface straight above faces up
  // (its underside is seen from inside), or the nearest one straight below faces down.
  bool InsideTerrain(const Eigen::Vector3d& p) const {
    const auto it = grid.find(Key(CellIndex(p.x()), CellIndex(p.y())));
    if (it == grid.end()) return false;
    double above = std::numeric_limits<double>::infinity();
    double below = -std::numeric_limits<double>::infinity();
    double above_nz = 0.0;
    double below_nz = 0.0;
    for (int index : it->second) {
      const auto& tri = ray_triangles[static_cast<std::size_t>(index)];
      const Eigen::Vector2d a = tri[0].head<2>(), b = tri[1].head<2>(), c = tri[2].head<2>();
      const Eigen::Vector2d q = p.head<2>();
      const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      if (std::abs(det) < 1e-18) continue;
      const double u = ((q - a).x() * (c - a).y() - (q - a).y() * (c - a).x()) / det;
      const double v = ((b - a).x() * (q - a).y() - (b - a).y() * (q - a).x()) / det;
      if (u < 0.0 || v < 0.0 || u + v > 1.0) continue;
      const double z = tri[0].z() + u * (tri[1].z() - tri[0].z()) + v * (tri[2].z() - tri[0].z());
      const double nz = ray_normal_z[static_cast<std::size_t>(index)];
      if (z >= p.z() && z < above) {
        above = z;
        above_nz = nz;
      }
      if (z < p.z() && z > below) {
        below = z;
        below_nz = nz;
      }
    }
    return above_nz > 0.0 || below_nz < 0.0;
  }

  bool TrunkCollides(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) {
    const Aabb box = Moved(trunk_local_box, R, p);
    if (InsideTerrain(p)) return true;
    if (!box.Overlaps(terrain_box)) return false;
    return TrunkTouchesTriangles(R, p, box);
  }

  bool Touches(Rom& rom, const Aabb& box, const Eigen::Matrix3d& R, const Eigen::Vector3d& p, int surface) {
    const Surface& s = surfaces[static_cast<std::size_t>(surface)];
    if (!box.Overlaps(s.box)) return false;
    // The prism in the ROM's frame against the ROM's cross-sections over the heights it spans.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Eigen::Vector3d& c : s.corners) {
      const Eigen::Vector3d q = R.transpose() * (c - p);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    if (!rom.slabs.MayOverlap(lo.z(), hi.z(), lo.head<2>(), hi.head<2>())) return false;
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    return fcl::collide(rom.object.get(), s.object.get(), request, result) > 0;
  }

  // Index of a surface the leg's ROM intersects, or -1. The surface found last time is tried
  // first: along a path the same surface usually stays in reach.
  int LegSurface(Leg leg, const Eigen::Matrix3d& R, const Eigen::Vector3d& p) {
    const std::size_t l = static_cast<std::size_t>(Index(leg));
    Rom& rom = roms[l];
    const Aabb box = Moved(rom.local_box, R, p);
    rom.object->setTransform(R, p);
    rom.object->computeAABB();
    const int last = last_surface[l];
    if (last >= 0 && Touches(rom, box, R, p, last)) return last;
    for (int s = 0; s < static_cast<int>(surfaces.size()); ++s) {
      if (s != last && Touches(rom, box, R, p, s)) {
        last_surface[l] = s;
        return s;
      }
    }
    return -1;
  }
};

ReachabilityChecker::ReachabilityChecker(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                                         const std::array<ConvexPolytope, kNumLegs>& roms, const ConvexPolytope& trunk,
                                         double surface_depth)
    : impl_(std::make_unique<Impl>()) {
  const std::string problem = ValidateMesh(terrain);
  if (!problem.empty()) throw InputError("reachability checker: expected a valid terrain mesh, got: " + problem);
  if (!(surface_depth > 0.0)) throw InputError("reachability checker: expected a surface depth > 0 m");
  Impl& m = *impl_;
  m.terrain_box = Bounds(terrain.vertices);
  m.ChooseCell(terrain);
  m.BuildRayGrid(terrain);
  m.BuildBoxGrid(terrain);

  m.trunk.emplace(trunk);
  m.trunk_local_box = Bounds(trunk.vertices);
  for (Leg leg : kAllLegs) {
    const std::size_t l = static_cast<std::size_t>(Index(leg));
    m.roms[l].geometry = MakeConvex(roms[l]);
    m.roms[l].object = std::make_unique<fcl::CollisionObjectd>(m.roms[l].geometry);
    m.roms[l].local_box = Bounds(roms[l].vertices);
    m.roms[l].slabs = SlabBounds(roms[l], Impl::kRomSlabs);
  }
  m.surfaces.reserve(surfaces.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const AffordanceSurface& s = surfaces[i];
    const int n = static_cast<int>(s.vertices.size());
    if (n < 3 || !(std::abs(s.normal.norm() - 1.0) < 1e-6)) {
      throw InputError("reachability checker: surface " + std::to_string(i) +
                       ": expected a polygon of at least 3 vertices with a unit normal");
    }
    // Prism: the polygon on top, the same polygon surface_depth below, side quads.
    std::vector<Eigen::Vector3d> prism;
    for (const auto& v : s.vertices) prism.push_back(v);
    for (const auto& v : s.vertices) prism.push_back(v - surface_depth * s.normal);
    std::vector<std::vector<int>> faces;
    std::vector<int> top, bottom;
    for (int k = 0; k < n; ++k) {
      top.push_back(k);
      bottom.push_back(2 * n - 1 - k);
      const int k1 = (k + 1) % n;
      faces.push_back({k, n + k, n + k1, k1});
    }
    faces.push_back(top);
    faces.push_back(bottom);
    Impl::Surface surface;
    surface.geometry = MakeConvex(prism, faces);
    surface.object = std::make_unique<fcl::CollisionObjectd>(surface.geometry);
    surface.object->computeAABB();
    surface.box = Bounds(prism);
    surface.corners = prism;
    m.surfaces.push_back(std::move(surface));
  }
}

ReachabilityChecker::~ReachabilityChecker() = default;
ReachabilityChecker::ReachabilityChecker(ReachabilityChecker&&) noexcept = default;
ReachabilityChecker& ReachabilityChecker::operator=(ReachabilityChecker&&) noexcept = default;

bool ReachabilityChecker::IsValid(const Eigen::Vector3d& p_W, double yaw) {
  Impl& m = *impl_;
  ++m.queries;
  const Eigen::Matrix3d R = YawRotation(yaw);
  for (Leg leg : kAllLegs) {
    if (m.LegSurface(leg, R, p_W) < 0) return false;
  }
  return !m.TrunkCollides(R, p_W);
}

ReachabilityReport ReachabilityChecker::Check(const Eigen::Vector3d& p_W, double yaw) {
  Impl& m = *impl_;
  ++m.queries;
  const Eigen::Matrix3d R = YawRotation(yaw);
  ReachabilityReport report;
  report.trunk_collision = m.TrunkCollides(R, p_W);
  for (Leg leg : kAllLegs) report.leg_surface[static_cast<std::size_t>(Index(leg))] = m.LegSurface(leg, R, p_W);
  return report;
}

bool ReachabilityChecker::TrunkCollides(const Eigen::Vector3d& p_W, double yaw) {
  return impl_->TrunkCollides(YawRotation(yaw), p_W);
}

long ReachabilityChecker::Queries() const { return impl_->queries; }
std::size_t ReachabilityChecker::NumSurfaces() const { return impl_->surfaces.size(); }

}  // namespace rbcp
