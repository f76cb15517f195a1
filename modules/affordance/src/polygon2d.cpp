#include "polygon2d.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace rbcp::polygon2d {

double SignedArea(const Ring& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return 0.0;
  // Relative to the first vertex, which keeps the sum accurate far from the origin.
  const Point& o = ring[0];
  double twice = 0.0;
  for (std::size_t i = 1; i + 1 < n; ++i) twice += Cross(o, ring[i], ring[i + 1]);
  return 0.5 * twice;
}

double Area(const PolygonWithHoles& polygon) {
  double area = SignedArea(polygon.outer);
  for (const Ring& hole : polygon.holes) area += SignedArea(hole);  // holes are negative
  return area;
}

namespace {

bool Removable(const Point& a, const Point& b, const Point& c, double tol) {
  const double tol2 = tol * tol;
  const double ac2 = (c - a).squaredNorm();
  if (ac2 <= tol2) return true;  // a zero-width spike, or b repeats a and c
  if ((b - a).squaredNorm() <= tol2 || (c - b).squaredNorm() <= tol2) return true;
  const double cross = Cross(a, b, c);
  return cross * cross <= tol2 * ac2;  // b within tol of the line through a and c
}

/// Whether a direction lies in the half-turn of angles [0, pi).
bool UpperHalf(const Point& d) { return d.y() > 0.0 || (d.y() == 0.0 && d.x() > 0.0); }

}  // namespace

void RemoveCollinear(Ring& ring, double tolerance) {
  // Stack pass over the ring, then repair the seam where the last vertex meets the first.
  std::size_t w = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    ring[w++] = ring[i];
    while (w >= 3 && Removable(ring[w - 3], ring[w - 2], ring[w - 1], tolerance)) {
      ring[w - 2] = ring[w - 1];
      --w;
    }
  }
  std::size_t s = 0;  // first live vertex
  bool changed = true;
  while (changed && w - s >= 3) {
    changed = false;
    if (Removable(ring[w - 2], ring[w - 1], ring[s], tolerance)) {
      --w;
      changed = true;
    } else if (Removable(ring[w - 1], ring[s], ring[s + 1], tolerance)) {
      ++s;
      changed = true;
    }
  }
  if (w - s < 3) {
    ring.clear();
    return;
  }
  if (s > 0)
    std::move(ring.begin() + static_cast<std::ptrdiff_t>(s), ring.begin() + static_cast<std::ptrdiff_t>(w),
              ring.begin());
  ring.resize(w - s);
}

bool IsConvex(const Ring& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return false;
  // Left turns only, and the edge direction passes angle 0 once: one full turn, not a star.
  int windings = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Point& a = ring[(i + n - 1) % n];
    const Point& b = ring[i];
    const Point& c = ring[(i + 1) % n];
    if (!(Cross(a, b, c) > 0.0)) return false;
    if (!UpperHalf(b - a) && UpperHalf(c - b)) ++windings;
  }
  return windings == 1;
}

void ErodeConvex(const Ring& convex, double margin, Ring& out, Ring& scratch) {
  out.assign(convex.begin(), convex.end());
  if (margin <= 0.0) return;
  const std::size_t n = convex.size();
  // Usually every edge survives: then vertex i of the result is where the shifted lines of
  // edges i - 1 and i meet. Accept that when each new edge keeps its direction.
  scratch.resize(n);  // unit edge directions
  for (std::size_t i = 0; i < n; ++i) scratch[i] = (convex[(i + 1) % n] - convex[i]).normalized();
  // Edge i's shifted line: normal . x = offset, with the inward normal (-t.y, t.x).
  const auto offset = [&](std::size_t i) { return Cross(Point::Zero(), scratch[i], convex[i]) + margin; };
  bool kept = true;
  for (std::size_t i = 0; i < n && kept; ++i) {
    const std::size_t h = (i + n - 1) % n;
    const Point& t0 = scratch[h];
    const Point& t1 = scratch[i];
    const double det = t0.x() * t1.y() - t0.y() * t1.x();  // sine of the turn
    kept = det > 1e-6;                                     // a nearly straight vertex is left to the clipping below
    const double c0 = offset(h);
    const double c1 = offset(i);
    out[i] = Point((c0 * t1.x() - c1 * t0.x()) / det, (c0 * t1.y() - c1 * t0.y()) / det);
  }
  for (std::size_t i = 0; i < n && kept; ++i) kept = (out[(i + 1) % n] - out[i]).dot(scratch[i]) > kLinearTolerance;
  if (kept) {
    if (SignedArea(out) <= 0.0) out.clear();
    return;
  }
  // Some edges vanish: clip by the shifted half-planes one at a time.
  out.assign(convex.begin(), convex.end());
  for (std::size_t i = 0; i < n && out.size() >= 3; ++i) {
    const Point& a = convex[i];
    const Point t = (convex[(i + 1) % n] - a).normalized();
    const Point normal(-t.y(), t.x());  // inward: the interior is on the left
    const double offset = normal.dot(a) + margin;
    scratch.clear();
    const std::size_t k = out.size();
    for (std::size_t j = 0; j < k; ++j) {
      const Point& p = out[j];
      const Point& q = out[(j + 1) % k];
      const double dp = normal.dot(p) - offset;
      const double dq = normal.dot(q) - offset;
      if (dp >= 0.0) scratch.push_back(p);
      if ((dp >= 0.0) != (dq >= 0.0)) {
        Point x = p + (dp / (dp - dq)) * (q - p);
        x += (offset - normal.dot(x)) * normal;  // onto the clipping line
        scratch.push_back(x);
      }
    }
    out.swap(scratch);
  }
  RemoveCollinear(out);
  if (out.size() < 3 || SignedArea(out) <= 0.0) out.clear();
}

double DistanceToSegment(const Point& p, const Point& a, const Point& b) {
  const Point ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

bool Contains(const Ring& ring, const Point& p) {
  bool inside = false;
  const std::size_t n = ring.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Point& a = ring[i];
    const Point& b = ring[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

namespace {

/// Ear clipping over a doubly linked vertex list; holes are joined to the outer ring by
/// bridges (two coincident copies of each bridge end), so the list stays one weakly simple ring.
class EarClipper {
 public:
  explicit EarClipper(const std::vector<Point>& points) : points_(points) {}

  /// Links points [first, first + count) into a ring; returns its first node.
  int AddRing(int first, int count) {
    const int start = static_cast<int>(nodes_.size());
    for (int i = 0; i < count; ++i) {
      nodes_.push_back({first + i, start + (i + count - 1) % count, start + (i + 1) % count});
    }
    return start;
  }

  /// Bridges each hole (given by one of its nodes) into the ring of `outer`.
  bool EliminateHoles(int outer, std::vector<int> holes) {
    // The vertex of largest x of each hole, handled from the rightmost hole leftwards, so a bridge
    // (cast towards +x) never crosses a hole that is not yet joined.
    for (int& h : holes) {
      int best = h;
      for (int p = Next(h); p != h; p = Next(p)) {
        if (P(p).x() > P(best).x()) best = p;
      }
      h = best;
    }
    std::stable_sort(holes.begin(), holes.end(), [&](int a, int b) { return P(a).x() > P(b).x(); });
    for (int hole : holes) {
      const int bridge = FindHoleBridge(hole, outer);
      if (bridge < 0) return false;
      Split(bridge, hole);
    }
    return true;
  }

  /// Clips ears until the ring is used up; false if no ear can be found.
  bool Clip(int ear, std::vector<std::array<int, 3>>& triangles) {
    ear = Filter(ear);
    int stop = ear;
    bool filtered = false;
    while (Prev(ear) != Next(ear)) {
      const int a = Prev(ear);
      const int c = Next(ear);
      if (IsEar(ear)) {
        triangles.push_back({V(a), V(ear), V(c)});
        Remove(ear);
        ear = Next(c);
        stop = ear;
        continue;
      }
      ear = c;
      if (ear == stop) {
        if (filtered) return false;
        ear = Filter(ear);
        stop = ear;
        filtered = true;
      }
    }
    return true;
  }

 private:
  struct Node {
    int v;
    int prev;
    int next;
  };

  const Point& P(int n) const { return points_[static_cast<std::size_t>(nodes_[static_cast<std::size_t>(n)].v)]; }
  int V(int n) const { return nodes_[static_cast<std::size_t>(n)].v; }
  int Prev(int n) const { return nodes_[static_cast<std::size_t>(n)].prev; }
  int Next(int n) const { return nodes_[static_cast<std::size_t>(n)].next; }
  void Remove(int n) {
    nodes_[static_cast<std::size_t>(Prev(n))].next = Next(n);
    nodes_[static_cast<std::size_t>(Next(n))].prev = Prev(n);
  }

  static bool InTriangle(const Point& a, const Point& b, const Point& c, const Point& p) {
    // Closed triangle, either orientation.
    const double d1 = Cross(a, b, p);
    const double d2 = Cross(b, c, p);
    const double d3 = Cross(c, a, p);
    const bool has_neg = d1 < 0.0 || d2 < 0.0 || d3 < 0.0;
    const bool has_pos = d1 > 0.0 || d2 > 0.0 || d3 > 0.0;
    return !(has_neg && has_pos);
  }

  /// Removes repeated and collinear vertices; returns a node still in the ring.
  int Filter(int start) {
    int end = start;
    int p = start;
    bool again = false;
    do {
      again = false;
      const int n = Next(p);
      if (p != n && (P(p) == P(n) || Removable(P(Prev(p)), P(p), P(n), kLinearTolerance))) {
        const int before = Prev(p);
        Remove(p);
        p = end = before;
        if (p == Next(p)) break;
        again = true;
      } else {
        p = n;
      }
    } while (again || p != end);
    return end;
  }

  bool IsEar(int ear) const {
    const Point& a = P(Prev(ear));
    const Point& b = P(ear);
    const Point& c = P(Next(ear));
    if (!(Cross(a, b, c) > 0.0)) return false;
    for (int p = Next(Next(ear)); p != Prev(ear); p = Next(p)) {
      const Point& q = P(p);
      if (q == a || q == b || q == c) continue;  // a bridge copy of a corner
      if (InTriangle(a, b, c, q)) return false;
    }
    return true;
  }

  /// Whether the diagonal from node a towards point b starts inside the polygon at a.
  bool LocallyInside(int a, const Point& b) const {
    const Point& pa = P(a);
    const Point& prev = P(Prev(a));
    const Point& next = P(Next(a));
    if (Cross(prev, pa, next) < 0.0) return Cross(pa, prev, b) <= 0.0 || Cross(pa, b, next) <= 0.0;
    return Cross(pa, next, b) >= 0.0 && Cross(pa, b, prev) >= 0.0;
  }

  /// A vertex of the outer ring visible from the hole vertex `hole` (Eberly's ray to +x).
  int FindHoleBridge(int hole, int outer) const {
    const Point h = P(hole);
    double qx = std::numeric_limits<double>::infinity();
    int m = -1;
    int p = outer;
    do {
      const Point& a = P(p);
      const Point& b = P(Next(p));
      // Seen from inside, the ray leaves through an edge that runs upwards.
      if (a.y() <= h.y() && h.y() <= b.y() && a.y() != b.y()) {
        const double x = a.x() + (h.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
        if (x >= h.x() && x < qx) {
          qx = x;
          m = a.x() > b.x() ? p : Next(p);
          if (x == h.x()) {  // the hole touches the ring here
            if (a == h) return p;
            if (b == h) return Next(p);
            return m;
          }
        }
      }
      p = Next(p);
    } while (p != outer);
    if (m < 0) return -1;
    // Vertices inside the triangle (hole, ray hit, m) may hide m; take the one at the smallest
    // angle from the ray.
    const int stop = m;
    const Point tip = P(m);
    const Point hit(qx, h.y());
    double tan_min = std::numeric_limits<double>::infinity();
    p = m;
    do {
      const Point& q = P(p);
      if (h.x() <= q.x() && q.x() <= tip.x() && h.x() != q.x() && InTriangle(h, hit, tip, q)) {
        const double tan = std::abs(h.y() - q.y()) / (q.x() - h.x());
        if (LocallyInside(p, h) && (tan < tan_min || (tan == tan_min && q.x() < P(m).x()))) {
          m = p;
          tan_min = tan;
        }
      }
      p = Next(p);
    } while (p != stop);
    return m;
  }

  /// Joins a (outer) and b (hole) by a two-way bridge a -> b ... b' -> a'.
  void Split(int a, int b) {
    const int a2 = static_cast<int>(nodes_.size());
    const int b2 = a2 + 1;
    const int an = Next(a);
    const int bp = Prev(b);
    nodes_.push_back({V(a), b2, an});
    nodes_.push_back({V(b), bp, a2});
    nodes_[static_cast<std::size_t>(a)].next = b;
    nodes_[static_cast<std::size_t>(b)].prev = a;
    nodes_[static_cast<std::size_t>(an)].prev = a2;
    nodes_[static_cast<std::size_t>(bp)].next = b2;
  }

  const std::vector<Point>& points_;
  std::vector<Node> nodes_;
};

std::uint64_t EdgeKey(int u, int v) {
  const auto lo = static_cast<std::uint32_t>(std::min(u, v));
  const auto hi = static_cast<std::uint32_t>(std::max(u, v));
  return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

double Perimeter(const Ring& ring) {
  double length = 0.0;
  for (std::size_t i = 0; i < ring.size(); ++i) length += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  return length;
}

int Find(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

/// An edge two triangles share: the half-edge u -> v of triangle tri_uv and v -> u of tri_vu.
struct Diagonal {
  int u, v, tri_uv, tri_vu;
  double length2;  ///< squared length
};

/// The edges shared by exactly two triangles, in opposite directions: longest first.
std::vector<Diagonal> Diagonals(const std::vector<Point>& points, const std::vector<std::array<int, 3>>& triangles) {
  const int nt = static_cast<int>(triangles.size());
  struct HalfEdge {
    std::uint64_t key;
    int u, v, tri;
  };
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(static_cast<std::size_t>(3 * nt));
  for (int t = 0; t < nt; ++t) {
    const auto& tri = triangles[static_cast<std::size_t>(t)];
    for (int k = 0; k < 3; ++k) {
      const int u = tri[static_cast<std::size_t>(k)];
      const int v = tri[static_cast<std::size_t>((k + 1) % 3)];
      half_edges.push_back({EdgeKey(u, v), u, v, t});
    }
  }
  std::sort(half_edges.begin(), half_edges.end(),
            [](const HalfEdge& a, const HalfEdge& b) { return a.key != b.key ? a.key < b.key : a.tri < b.tri; });
  std::vector<Diagonal> diagonals;
  for (std::size_t i = 0; i < half_edges.size();) {
    std::size_t j = i + 1;
    while (j < half_edges.size() && half_edges[j].key == half_edges[i].key) ++j;
    if (j - i == 2 && half_edges[i].u == half_edges[i + 1].v) {
      const HalfEdge& e = half_edges[i];
      const double len2 = (points[static_cast<std::size_t>(e.u)] - points[static_cast<std::size_t>(e.v)]).squaredNorm();
      diagonals.push_back({e.u, e.v, e.tri, half_edges[i + 1].tri, len2});
    }
    i = j;
  }
  std::stable_sort(diagonals.begin(), diagonals.end(),
                   [](const Diagonal& a, const Diagonal& b) { return a.length2 > b.length2; });
  return diagonals;
}

/// Whether the corner prev -> at -> next turns left (within the linear tolerance).
bool ConvexAt(const std::vector<Point>& points, int prev, int at, int next) {
  const auto pt = [&](int id) -> const Point& { return points[static_cast<std::size_t>(id)]; };
  return Cross(pt(prev), pt(at), pt(next)) >= -kLinearTolerance * (pt(next) - pt(prev)).norm();
}

/// The pieces pa (which runs u -> v along the diagonal) and pb (v -> u) joined across diagonal d
/// into `merged`; false when they do not border on it or the joined piece is not convex at u or v.
bool MergeAcross(const std::vector<Point>& points, const Diagonal& d, const std::vector<int>& pa,
                 const std::vector<int>& pb, std::vector<int>& merged) {
  const int na = static_cast<int>(pa.size());
  const int nb = static_cast<int>(pb.size());
  int ia = -1;
  int ib = -1;
  for (int i = 0; i < na; ++i) {
    if (pa[static_cast<std::size_t>(i)] == d.u && pa[static_cast<std::size_t>((i + 1) % na)] == d.v) ia = i;
  }
  for (int i = 0; i < nb; ++i) {
    if (pb[static_cast<std::size_t>(i)] == d.v && pb[static_cast<std::size_t>((i + 1) % nb)] == d.u) ib = i;
  }
  if (ia < 0 || ib < 0) return false;
  const auto at_a = [&](int i) { return pa[static_cast<std::size_t>(((i % na) + na) % na)]; };
  const auto at_b = [&](int i) { return pb[static_cast<std::size_t>(((i % nb) + nb) % nb)]; };
  // A: u -> v -> ... ; B: v -> u -> ... . Merged: u, B after u .. before v, v, A after v .. before u.
  if (!ConvexAt(points, at_a(ia - 1), d.u, at_b(ib + 2)) || !ConvexAt(points, at_b(ib - 1), d.v, at_a(ia + 2))) {
    return false;
  }
  merged.clear();
  merged.push_back(d.u);
  for (int i = 2; i < nb; ++i) merged.push_back(at_b(ib + i));
  merged.push_back(d.v);
  for (int i = 2; i < na; ++i) merged.push_back(at_a(ia + i));
  return true;
}

/// Hertel-Mehlhorn: drop every diagonal whose removal leaves a convex piece, longest first.
void MergeConvex(const std::vector<Point>& points, const std::vector<std::array<int, 3>>& triangles,
                 std::vector<Ring>& pieces) {
  // Each triangle starts as its own piece; `parent` finds the piece a triangle was merged into.
  const int nt = static_cast<int>(triangles.size());
  std::vector<std::vector<int>> piece(static_cast<std::size_t>(nt));
  std::vector<int> parent(static_cast<std::size_t>(nt));
  for (int t = 0; t < nt; ++t) {
    const auto& tri = triangles[static_cast<std::size_t>(t)];
    piece[static_cast<std::size_t>(t)].assign(tri.begin(), tri.end());
    parent[static_cast<std::size_t>(t)] = t;
  }
  std::vector<int> merged;
  for (const Diagonal& d : Diagonals(points, triangles)) {
    const int a = Find(parent, d.tri_uv);
    const int b = Find(parent, d.tri_vu);
    if (a == b) continue;
    if (!MergeAcross(points, d, piece[static_cast<std::size_t>(a)], piece[static_cast<std::size_t>(b)], merged)) continue;
    piece[static_cast<std::size_t>(a)].swap(merged);
    piece[static_cast<std::size_t>(b)].clear();
    parent[static_cast<std::size_t>(b)] = a;
  }

  for (const std::vector<int>& ids : piece) {
    if (ids.empty()) continue;
    Ring ring;
    ring.reserve(ids.size());
    for (int id : ids) ring.push_back(points[static_cast<std::size_t>(id)]);
    RemoveCollinear(ring);
    if (ring.size() >= 3 && SignedArea(ring) > 0.0) pieces.push_back(std::move(ring));
  }
}

}  // namespace

bool ConvexPartition(const PolygonWithHoles& polygon, std::vector<Ring>& pieces) {
  pieces.clear();
  std::vector<Point> points(polygon.outer.begin(), polygon.outer.end());
  for (const Ring& hole : polygon.holes) points.insert(points.end(), hole.begin(), hole.end());
  if (polygon.outer.size() < 3) return false;

  EarClipper clipper(points);
  const int outer = clipper.AddRing(0, static_cast<int>(polygon.outer.size()));
  std::vector<int> holes;
  int first = static_cast<int>(polygon.outer.size());
  for (const Ring& hole : polygon.holes) {
    if (hole.size() >= 3) holes.push_back(clipper.AddRing(first, static_cast<int>(hole.size())));
    first += static_cast<int>(hole.size());
  }
  std::vector<std::array<int, 3>> triangles;
  if (!clipper.EliminateHoles(outer, holes) || !clipper.Clip(outer, triangles)) return false;

  // The triangles must tile the polygon; anything else means the input was not a valid polygon.
  double area = 0.0;
  for (const auto& t : triangles) {
    area += 0.5 * Cross(points[static_cast<std::size_t>(t[0])], points[static_cast<std::size_t>(t[1])],
                        points[static_cast<std::size_t>(t[2])]);
  }
  const double expected = Area(polygon);
  double perimeter = Perimeter(polygon.outer);
  for (const Ring& hole : polygon.holes) perimeter += Perimeter(hole);
  const double tolerance = 1e-9 * std::max(1.0, std::abs(expected)) + 2.0 * kLinearTolerance * perimeter;
  if (!(std::abs(area - expected) <= tolerance)) return false;

  MergeConvex(points, triangles, pieces);
  return true;
}

}  // namespace rbcp::polygon2d
