#include "rbcp/affordance/affordance_extractor.h"

#include <algorithm>
#include <unordered_set>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "polygon2d.h"
#include "polygon_offset.h"
#include "rbcp/core/error.h"

namespace rbcp {
namespace {

using polygon2d::Point;
using polygon2d::PolygonWithHoles;
using polygon2d::Ring;

constexpr double kDegToRad = M_PI / 180.0;
/// Welding grid: cells much larger than the weld tolerance, so a vertex rarely needs to look
/// into a neighbouring cell; shifted so round coordinates do not sit on cell faces.
constexpr double kWeldCell = 1e-3;
constexpr double kWeldGridShift = 0.3713;
/// Boundary loops enclosing less than this are slivers of the mesh, not surface [m^2].
constexpr double kMinLoopArea = 1e-14;

std::uint64_t Mix(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

std::uint64_t Bits(double d) {
  std::uint64_t u = 0;
  std::memcpy(&u, &d, sizeof(u));
  return u;
}

/// floor() without a libm call on targets lacking a rounding instruction.
double Floor(double s) {
  if (!(std::abs(s) < 1e18)) return std::floor(s);
  const double f = static_cast<double>(static_cast<std::int64_t>(s));
  return f > s ? f - 1.0 : f;
}

std::size_t TableSize(std::size_t entries) {
  std::size_t size = 16;
  while (size < 2 * entries) size *= 2;
  return size;
}

/// The plane of a region and an orthonormal frame in it: e1 x e2 = normal, so counter-clockwise
/// in (e1, e2) coordinates is counter-clockwise seen from the normal side.
struct RegionPlane {
  Eigen::Vector3d normal;
  Eigen::Vector3d e1;
  Eigen::Vector3d e2;
  double offset;  ///< normal . x on the plane [m]
  double area;    ///< of the region's triangles [m^2]

  Point Project(const Eigen::Vector3d& p) const { return {e1.dot(p), e2.dot(p)}; }
  Eigen::Vector3d Lift(const Point& q) const { return offset * normal + q.x() * e1 + q.y() * e2; }
};

/// Writes the surfaces into the caller's vector in order, reusing the storage of the entries it
/// already holds (the caller trims it to `count` at the end).
struct SurfaceWriter {
  std::vector<AffordanceSurface>& surfaces;
  std::size_t count = 0;

  /// The next surface: a ring of the region's plane lifted back to 3D, with its area [m^2].
  void Write(const RegionPlane& plane, const Ring& ring, double ring_area) {
    if (surfaces.size() <= count) surfaces.emplace_back();
    AffordanceSurface& s = surfaces[count++];
    s.vertices.clear();
    s.vertices.reserve(ring.size());
    for (const Point& q : ring) s.vertices.push_back(plane.Lift(q));
    s.normal = plane.normal;
    s.area = ring_area;
  }
};

/// How the boundary loops of a region divide: counter-clockwise outer rings, clockwise holes.
struct LoopCounts {
  int outer = 0;
  int holes = 0;
  const Ring* last_outer = nullptr;  ///< the only outer ring when outer == 1
};

}  // namespace

struct AffordanceExtractor::Workspace {
  // Candidate triangles (facing up within the inclination limit), in mesh order.
  struct CornersHash {
    std::size_t operator()(const std::array<int, 3>& c) const {
      return std::hash<uint64_t>()((static_cast<uint64_t>(static_cast<uint32_t>(c[0])) * 0x9E3779B97F4A7C15ULL) ^
                                   (static_cast<uint64_t>(static_cast<uint32_t>(c[1])) << 21) ^
                                   static_cast<uint64_t>(static_cast<uint32_t>(c[2])));
    }
  };
  std::unordered_set<std::array<int, 3>, CornersHash> seen_triangles;  // sorted welded corners of the kept triangles
  std::vector<int> candidate_triangle;            // mesh triangle index
  std::vector<Eigen::Vector3d> candidate_normal;  // unit
  std::vector<double> candidate_area;             // [m^2]
  std::vector<std::array<int, 3>> corner;         // welded vertex ids

  // Welding: mesh vertex -> welded id; welded id -> position; open-addressing grid hash.
  struct WeldSlot {
    double cx, cy, cz;  // cell coordinates
    int id;             // welded id, -1 for an empty slot
  };
  std::vector<int> welded_id;
  std::vector<Eigen::Vector3d> welded;
  std::vector<WeldSlot> weld_table;

  // Half-edge he = 3 * candidate + k runs from corner[c][k] to corner[c][(k + 1) % 3].
  struct EdgeSlot {
    std::uint64_t key;  // from << 32 | to
    int he;             // -1 empty, -2 the directed edge occurs more than once
  };
  std::vector<EdgeSlot> edge_table;
  std::vector<int> twin;  // opposite half-edge in an edge shared by exactly two triangles, or -1

  // Region growing.
  std::vector<int> region_of;  // per candidate, -1 unassigned
  std::vector<int> stack;
  std::vector<int> members;  // candidates of the region being processed

  // Boundary chaining.
  std::vector<int> out_head;  // welded vertex -> a boundary half-edge leaving it, -1 none
  std::vector<int> out_next;  // boundary half-edge -> next one leaving the same vertex
  std::vector<char> used;
  std::vector<int> boundary;
  std::vector<Ring> loops;  // storage reused across regions; the first `num_loops` are live
  std::size_t num_loops = 0;

  // Plane polygons.
  Ring eroded;
  Ring scratch;
  std::vector<Ring> pieces;
  std::vector<PolygonWithHoles> polygons;
  std::vector<PolygonWithHoles> eroded_polygons;

  const Eigen::Vector3d& Pos(int welded_vertex) const { return welded[static_cast<std::size_t>(welded_vertex)]; }
  int From(int he) const { return corner[static_cast<std::size_t>(he / 3)][static_cast<std::size_t>(he % 3)]; }
  int To(int he) const { return corner[static_cast<std::size_t>(he / 3)][static_cast<std::size_t>((he + 1) % 3)]; }

  /// Candidate triangles; false if the mesh has an out-of-range index.
  bool CollectCandidates(const TriangleMesh& mesh, double cos_inclination, AffordanceStats& stats);
  /// Welded corners of the candidates; drops those with two corners welded together.
  void WeldCandidates(const TriangleMesh& mesh, AffordanceStats& stats);
  int Weld(const Eigen::Vector3d& p);
  void BuildTwins();
  /// Fills `members` with the region grown from `seed`.
  void GrowRegion(std::size_t seed, int region, double cos_neighbour);
  RegionPlane FitPlane(std::size_t seed) const;
  /// Fills loops[0 .. num_loops) with the region's cleaned boundary loops in the plane.
  void ChainBoundary(int region, const RegionPlane& plane);
  LoopCounts CountLoops() const;
  /// Writes the surfaces of the region whose boundary loops ChainBoundary found: its polygons
  /// eroded by the edge margin and split into convex pieces.
  void WriteRegionSurfaces(const RegionPlane& plane, const AffordanceConfig& config, AffordanceStats& stats,
                           SurfaceWriter& out);
  /// Fills `polygons` with the outer loops, each with the holes it encloses.
  void AssignHoles();
  /// Writes the convex pieces of `eroded_polygons` larger than min_area [m^2]; false when none is.
  bool WriteConvexPieces(const RegionPlane& plane, double min_area, AffordanceStats& stats, SurfaceWriter& out);
};

bool AffordanceExtractor::Workspace::CollectCandidates(const TriangleMesh& mesh, double cos_inclination,
                                                       AffordanceStats& stats) {
  candidate_triangle.clear();
  candidate_normal.clear();
  candidate_area.clear();
  const std::size_t nv = mesh.vertices.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (static_cast<std::size_t>(static_cast<unsigned>(tri[0])) >= nv ||
        static_cast<std::size_t>(static_cast<unsigned>(tri[1])) >= nv ||
        static_cast<std::size_t>(static_cast<unsigned>(tri[2])) >= nv) {
      return false;
    }
    const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Eigen::Vector3d n = (mesh.vertices[static_cast<std::size_t>(tri[1])] - a)
                                  .cross(mesh.vertices[static_cast<std::size_t>(tri[2])] - a);
    const double twice_area2 = n.squaredNorm();
    if (!(twice_area2 > 4.0 * kMinTriangleArea * kMinTriangleArea) || !std::isfinite(twice_area2)) {
      ++stats.degenerate_triangles;
      continue;
    }
    // n.z >= cos * |n|, without a square root for walls and downward faces.
    if (n.z() <= 0.0 || n.z() * n.z() < cos_inclination * cos_inclination * twice_area2) continue;
    const double twice_area = std::sqrt(twice_area2);
    candidate_triangle.push_back(static_cast<int>(t));
    candidate_normal.push_back(n / twice_area);
    candidate_area.push_back(0.5 * twice_area);
  }
  return true;
}

void AffordanceExtractor::Workspace::WeldCandidates(const TriangleMesh& mesh, AffordanceStats& stats) {
  welded_id.assign(mesh.vertices.size(), -1);
  welded.clear();
  seen_triangles.clear();
  weld_table.assign(TableSize(3 * candidate_triangle.size()), WeldSlot{0.0, 0.0, 0.0, -1});
  corner.resize(candidate_triangle.size());
  std::size_t kept = 0;
  for (std::size_t c = 0; c < candidate_triangle.size(); ++c) {
    const auto& tri = mesh.triangles[static_cast<std::size_t>(candidate_triangle[c])];
    std::array<int, 3> ids{};
    for (std::size_t k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(tri[k]);
      if (welded_id[v] < 0) welded_id[v] = Weld(mesh.vertices[v]);
      ids[k] = welded_id[v];
    }
    if (ids[0] == ids[1] || ids[1] == ids[2] || ids[2] == ids[0]) {
      ++stats.degenerate_triangles;
      continue;
    }
    // A triangle listed twice (the same welded corners, facing up both times) is one triangle:
    // copies would each grow a region of their own and give the same surface many times.
    std::array<int, 3> sorted = ids;
    std::sort(sorted.begin(), sorted.end());
    if (!seen_triangles.insert(sorted).second) {
      ++stats.duplicate_triangles;
      continue;
    }
    candidate_triangle[kept] = candidate_triangle[c];
    candidate_normal[kept] = candidate_normal[c];
    candidate_area[kept] = candidate_area[c];
    corner[kept] = ids;
    ++kept;
  }
  candidate_triangle.resize(kept);
  candidate_normal.resize(kept);
  candidate_area.resize(kept);
  corner.resize(kept);
}

int AffordanceExtractor::Workspace::Weld(const Eigen::Vector3d& p) {
  const std::size_t mask = weld_table.size() - 1;
  double cell[3];
  int lo[3];  // neighbouring cells to search: -1 or 0 below, 0 or +1 above
  int hi[3];
  for (int a = 0; a < 3; ++a) {
    const double s = p[a] * (1.0 / kWeldCell) + kWeldGridShift;
    cell[a] = Floor(s);
    const double frac = (s - cell[a]) * kWeldCell;  // [m] into the cell
    lo[a] = frac < kWeldTolerance ? -1 : 0;
    hi[a] = kWeldCell - frac < kWeldTolerance ? 1 : 0;
  }
  const auto slot_of = [&](double cx, double cy, double cz) {
    return static_cast<std::size_t>(
               Mix(Bits(cx) ^ (Bits(cy) * 0x9e3779b97f4a7c15ULL) ^ (Bits(cz) * 0xc2b2ae3d27d4eb4fULL))) &
           mask;
  };
  int found = -1;  // the lowest id within the tolerance, so the result does not depend on probing
  const auto search = [&](double cx, double cy, double cz) {
    for (std::size_t s = slot_of(cx, cy, cz);; s = (s + 1) & mask) {
      const WeldSlot& slot = weld_table[s];
      if (slot.id < 0) return;
      if (slot.cx == cx && slot.cy == cy && slot.cz == cz &&
          (Pos(slot.id) - p).squaredNorm() <= kWeldTolerance * kWeldTolerance && (found < 0 || slot.id < found)) {
        found = slot.id;
      }
    }
  };
  for (int dx = lo[0]; dx <= hi[0]; ++dx) {
    for (int dy = lo[1]; dy <= hi[1]; ++dy) {
      for (int dz = lo[2]; dz <= hi[2]; ++dz) search(cell[0] + dx, cell[1] + dy, cell[2] + dz);
    }
  }
  if (found >= 0) return found;
  const int id = static_cast<int>(welded.size());
  welded.push_back(p);
  std::size_t s = slot_of(cell[0], cell[1], cell[2]);
  while (weld_table[s].id >= 0) s = (s + 1) & mask;
  weld_table[s] = {cell[0], cell[1], cell[2], id};
  return id;
}

void AffordanceExtractor::Workspace::BuildTwins() {
  const std::size_t num_he = 3 * corner.size();
  edge_table.assign(TableSize(num_he), EdgeSlot{0, -1});
  const std::size_t mask = edge_table.size() - 1;
  const auto key_of = [&](std::size_t he) {
    const auto from = static_cast<std::uint32_t>(From(static_cast<int>(he)));
    const auto to = static_cast<std::uint32_t>(To(static_cast<int>(he)));
    return (static_cast<std::uint64_t>(from) << 32) | to;
  };
  const auto find = [&](std::uint64_t key) -> EdgeSlot& {
    std::size_t s = static_cast<std::size_t>(Mix(key)) & mask;
    while (edge_table[s].he != -1 && edge_table[s].key != key) s = (s + 1) & mask;
    return edge_table[s];
  };
  for (std::size_t he = 0; he < num_he; ++he) {
    const std::uint64_t key = key_of(he);
    EdgeSlot& slot = find(key);
    if (slot.he == -1) {
      slot = {key, static_cast<int>(he)};
    } else {
      slot.he = -2;
    }
  }
  twin.assign(num_he, -1);
  for (std::size_t he = 0; he < num_he; ++he) {
    const std::uint64_t key = key_of(he);
    if (find(key).he != static_cast<int>(he)) continue;  // the same directed edge twice: not manifold
    const std::uint64_t reverse = (key << 32) | (key >> 32);
    const int other = find(reverse).he;
    if (other >= 0) twin[he] = other;
  }
}

void AffordanceExtractor::Workspace::GrowRegion(std::size_t seed, int region, double cos_neighbour) {
  const Eigen::Vector3d seed_normal = candidate_normal[seed];
  const double seed_offset = seed_normal.dot(Pos(corner[seed][0]));
  members.clear();
  stack.clear();
  stack.push_back(static_cast<int>(seed));
  region_of[seed] = region;
  while (!stack.empty()) {
    const int c = stack.back();
    stack.pop_back();
    members.push_back(c);
    for (int k = 0; k < 3; ++k) {
      const int tw = twin[static_cast<std::size_t>(3 * c + k)];
      if (tw < 0) continue;
      const auto u = static_cast<std::size_t>(tw / 3);
      if (region_of[u] >= 0 || candidate_normal[u].dot(seed_normal) < cos_neighbour) continue;
      bool coplanar = true;
      for (int v : corner[u])
        coplanar = coplanar && std::abs(seed_normal.dot(Pos(v)) - seed_offset) <= kCoplanarTolerance;
      if (!coplanar) continue;
      region_of[u] = region;
      stack.push_back(static_cast<int>(u));
    }
  }
}

RegionPlane AffordanceExtractor::Workspace::FitPlane(std::size_t seed) const {
  RegionPlane plane;
  plane.area = 0.0;
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  for (int c : members) {
    plane.area += candidate_area[static_cast<std::size_t>(c)];
    normal_sum += candidate_area[static_cast<std::size_t>(c)] * candidate_normal[static_cast<std::size_t>(c)];
  }
  plane.normal = normal_sum.normalized();
  // Area-weighted mean of the corners' offsets, as deviations from the seed corner's offset, so an
  // exactly flat region keeps that offset exactly.
  const double offset0 = plane.normal.dot(Pos(corner[seed][0]));
  double deviation = 0.0;
  for (int c : members) {
    double d = 0.0;
    for (int v : corner[static_cast<std::size_t>(c)]) d += plane.normal.dot(Pos(v)) - offset0;
    deviation += candidate_area[static_cast<std::size_t>(c)] * d;
  }
  plane.offset = offset0 + deviation / (3.0 * plane.area);
  plane.e1 = (Eigen::Vector3d::UnitX() - plane.normal.x() * plane.normal).normalized();
  plane.e2 = plane.normal.cross(plane.e1);
  return plane;
}

void AffordanceExtractor::Workspace::ChainBoundary(int region, const RegionPlane& plane) {
  // Boundary half-edges: those whose twin is missing or in another region.
  boundary.clear();
  for (int c : members) {
    for (int k = 0; k < 3; ++k) {
      const int he = 3 * c + k;
      const int tw = twin[static_cast<std::size_t>(he)];
      if (tw >= 0 && region_of[static_cast<std::size_t>(tw / 3)] == region) continue;
      const auto from = static_cast<std::size_t>(From(he));
      boundary.push_back(he);
      used[static_cast<std::size_t>(he)] = 0;
      out_next[static_cast<std::size_t>(he)] = out_head[from];
      out_head[from] = he;
    }
  }
  // Chain them. Where the boundary passes a vertex twice (a hole touching the outer ring there),
  // take the sharpest right turn: the outer ring and the hole then stay separate simple loops
  // that touch at that vertex.
  num_loops = 0;
  for (int start : boundary) {
    if (used[static_cast<std::size_t>(start)]) continue;
    if (loops.size() <= num_loops) loops.emplace_back();
    Ring& ring = loops[num_loops++];
    ring.clear();
    int he = start;
    while (true) {
      used[static_cast<std::size_t>(he)] = 1;
      ring.push_back(plane.Project(Pos(From(he))));
      const int at = To(he);
      int next = -1;
      int options = 0;
      for (int o = out_head[static_cast<std::size_t>(at)]; o >= 0; o = out_next[static_cast<std::size_t>(o)]) {
        if (!used[static_cast<std::size_t>(o)] || o == start) {
          ++options;
          next = o;
        }
      }
      if (options > 1) {
        const Point p_at = plane.Project(Pos(at));
        const Point d_in = p_at - plane.Project(Pos(From(he)));
        double sharpest = 4.0;  // above any turn angle
        for (int o = out_head[static_cast<std::size_t>(at)]; o >= 0; o = out_next[static_cast<std::size_t>(o)]) {
          if (used[static_cast<std::size_t>(o)] && o != start) continue;
          const Point d_out = plane.Project(Pos(To(o))) - p_at;
          const double turn = std::atan2(d_in.x() * d_out.y() - d_in.y() * d_out.x(), d_in.dot(d_out));
          if (turn < sharpest) {
            sharpest = turn;
            next = o;
          }
        }
      }
      if (next < 0 || next == start) break;
      he = next;
    }
  }
  for (int he : boundary) out_head[static_cast<std::size_t>(From(he))] = -1;
  for (std::size_t i = 0; i < num_loops; ++i) {
    polygon2d::RemoveCollinear(loops[i]);
    if (std::abs(polygon2d::SignedArea(loops[i])) <= kMinLoopArea) loops[i].clear();
  }
}

void AffordanceExtractor::Workspace::WriteRegionSurfaces(const RegionPlane& plane, const AffordanceConfig& config,
                                                         AffordanceStats& stats, SurfaceWriter& out) {
  const LoopCounts counts = CountLoops();
  if (counts.outer == 0) {
    ++stats.vanished_regions;
    return;
  }
  // Convex without holes: exact half-plane intersection, no allocation.
  if (counts.outer == 1 && counts.holes == 0 && polygon2d::IsConvex(*counts.last_outer)) {
    ++stats.convex_regions;
    polygon2d::ErodeConvex(*counts.last_outer, config.edge_margin, eroded, scratch);
    const double eroded_area = eroded.empty() ? 0.0 : polygon2d::SignedArea(eroded);
    if (eroded_area > config.min_area) {
      out.Write(plane, eroded, eroded_area);
    } else {
      ++stats.vanished_regions;
    }
    return;
  }
  // General: holes to their outer rings; offset with tangent round joins; split into convex pieces.
  AssignHoles();
  if (config.edge_margin > 0.0) {
    if (!polygon2d::Erode(polygons, config.edge_margin, kErosionArcSegmentsPerCircle, eroded_polygons)) {
      ++stats.geometry_failures;
      return;
    }
  } else {
    eroded_polygons.swap(polygons);
  }
  if (!WriteConvexPieces(plane, config.min_area, stats, out)) ++stats.vanished_regions;
}

LoopCounts AffordanceExtractor::Workspace::CountLoops() const {
  LoopCounts counts;
  for (std::size_t i = 0; i < num_loops; ++i) {
    if (loops[i].empty()) continue;
    if (polygon2d::SignedArea(loops[i]) > 0.0) {
      ++counts.outer;
      counts.last_outer = &loops[i];
    } else {
      ++counts.holes;
    }
  }
  return counts;
}

void AffordanceExtractor::Workspace::AssignHoles() {
  // Each hole goes to the smallest outer ring around it (a hole's edge midpoint lies inside its
  // outer ring).
  polygons.clear();
  for (std::size_t i = 0; i < num_loops; ++i) {
    if (!loops[i].empty() && polygon2d::SignedArea(loops[i]) > 0.0) polygons.push_back({loops[i], {}});
  }
  for (std::size_t i = 0; i < num_loops; ++i) {
    const Ring& hole = loops[i];
    if (hole.empty() || polygon2d::SignedArea(hole) > 0.0) continue;
    std::size_t owner = 0;
    const Point probe = 0.5 * (hole[0] + hole[1]);
    double owner_area = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < polygons.size() && polygons.size() > 1; ++j) {
      const double a = polygon2d::SignedArea(polygons[j].outer);
      if (a < owner_area && polygon2d::Contains(polygons[j].outer, probe)) {
        owner = j;
        owner_area = a;
      }
    }
    polygons[owner].holes.push_back(hole);
  }
}

bool AffordanceExtractor::Workspace::WriteConvexPieces(const RegionPlane& plane, double min_area, AffordanceStats& stats,
                                                       SurfaceWriter& out) {
  bool any = false;
  for (const PolygonWithHoles& polygon : eroded_polygons) {
    if (!(polygon2d::Area(polygon) > min_area)) continue;
    if (polygon.holes.empty() && polygon2d::IsConvex(polygon.outer)) {
      out.Write(plane, polygon.outer, polygon2d::SignedArea(polygon.outer));
      any = true;
      continue;
    }
    if (!polygon2d::ConvexPartition(polygon, pieces)) {
      ++stats.geometry_failures;
      continue;
    }
    for (const Ring& piece : pieces) out.Write(plane, piece, polygon2d::SignedArea(piece));
    any = any || !pieces.empty();
  }
  return any;
}

AffordanceExtractor::AffordanceExtractor(AffordanceConfig config)
    : config_(config), ws_(std::make_unique<Workspace>()) {
  config_.Validate("affordance config");
}

AffordanceExtractor::~AffordanceExtractor() = default;
AffordanceExtractor::AffordanceExtractor(AffordanceExtractor&&) noexcept = default;
AffordanceExtractor& AffordanceExtractor::operator=(AffordanceExtractor&&) noexcept = default;

std::vector<AffordanceSurface> AffordanceExtractor::Extract(const TriangleMesh& terrain) {
  std::vector<AffordanceSurface> surfaces;
  surfaces.reserve(static_cast<std::size_t>(stats_.surfaces));  // terrains change little between calls
  Extract(terrain, surfaces);
  return surfaces;
}

void AffordanceExtractor::Extract(const TriangleMesh& terrain, std::vector<AffordanceSurface>& surfaces) {
  Workspace& ws = *ws_;
  stats_ = AffordanceStats{};
  stats_.triangles = static_cast<int>(terrain.triangles.size());
  const double cos_inclination = std::cos(config_.max_inclination_deg * kDegToRad);
  const double cos_neighbour = std::cos(config_.neighbour_angle_deg * kDegToRad);

  // 1. Validate, and keep the triangles facing up within the inclination limit.
  double poison = 0.0;  // becomes NaN if any coordinate is NaN or infinite
  for (const Eigen::Vector3d& v : terrain.vertices) poison += v.x() * 0.0 + v.y() * 0.0 + v.z() * 0.0;
  if (terrain.triangles.empty() || poison != 0.0 || !ws.CollectCandidates(terrain, cos_inclination, stats_)) {
    const std::string problem = ValidateMesh(terrain, 0.0);
    RBCP_CHECK(!problem.empty(), "the mesh check and ValidateMesh disagree");
    throw InputError("terrain mesh: " + problem);
  }

  // 2. Weld, 3. edge adjacency.
  ws.WeldCandidates(terrain, stats_);
  const std::size_t nc = ws.candidate_triangle.size();
  stats_.candidate_triangles = static_cast<int>(nc);
  stats_.welded_vertices = static_cast<int>(ws.welded.size());
  ws.BuildTwins();

  // 4. Grow regions from seeds in triangle order and turn each into surfaces at once: 5. its
  // boundary loops in the plane, 6. eroded and split into convex pieces.
  ws.region_of.assign(nc, -1);
  ws.out_head.assign(ws.welded.size(), -1);
  ws.out_next.resize(3 * nc);
  ws.used.resize(3 * nc);
  SurfaceWriter out{surfaces};
  for (std::size_t seed = 0; seed < nc; ++seed) {
    if (ws.region_of[seed] >= 0) continue;
    const int region = stats_.planar_regions++;
    ws.GrowRegion(seed, region, cos_neighbour);
    const RegionPlane plane = ws.FitPlane(seed);
    if (!(plane.area > config_.min_area) || plane.normal.z() < cos_inclination) continue;
    ++stats_.kept_regions;
    ws.ChainBoundary(region, plane);
    ws.WriteRegionSurfaces(plane, config_, stats_, out);
  }

  surfaces.resize(out.count);
  stats_.surfaces = static_cast<int>(out.count);
}

}  // namespace rbcp
