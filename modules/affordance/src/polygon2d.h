#pragma once
/// Plane polygon operations used by affordance extraction (plane frame, metres).
/// Rings are open (the first vertex is not repeated); outer rings are counter-clockwise and holes
/// clockwise, so the polygon interior is always on the left of every edge.

#include <Eigen/Core>
#include <vector>

namespace rbcp::polygon2d {

using Point = Eigen::Vector2d;
using Ring = std::vector<Point>;

struct PolygonWithHoles {
  Ring outer;               ///< counter-clockwise
  std::vector<Ring> holes;  ///< clockwise, inside `outer`
};

/// Vertices closer than this to the line through their neighbours are dropped by cleaning [m].
inline constexpr double kLinearTolerance = 1e-9;

/// (a - o) x (b - o): positive when o, a, b turn left.
inline double Cross(const Point& o, const Point& a, const Point& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Shoelace area, positive for a counter-clockwise ring.
double SignedArea(const Ring& ring);
/// Outer area minus the hole areas.
double Area(const PolygonWithHoles& polygon);

/// Drops, in place and without allocating, repeated vertices and vertices within `tolerance` of
/// the line through their neighbours (also zero-width spikes). A ring left with fewer than three
/// vertices is cleared.
void RemoveCollinear(Ring& ring, double tolerance = kLinearTolerance);

/// True for a counter-clockwise ring that turns strictly left at every vertex and winds once.
/// Expects a ring cleaned by RemoveCollinear.
bool IsConvex(const Ring& ring);

/// Exact inward offset of a convex counter-clockwise ring by `margin` >= 0: the intersection of
/// its edge half-planes shifted inward. `out` is cleared when nothing is left. Allocation-free
/// once `out` and `scratch` have grown.
void ErodeConvex(const Ring& convex, double margin, Ring& out, Ring& scratch);

/// Splits a polygon with holes into convex counter-clockwise pieces that tile it exactly:
/// ear-clipping triangulation with the holes bridged to the outer ring, then Hertel-Mehlhorn
/// merging (at most four times the minimum number of pieces). Returns false, with `pieces`
/// cleared, when the polygon is too degenerate to triangulate.
bool ConvexPartition(const PolygonWithHoles& polygon, std::vector<Ring>& pieces);

/// Distance from p to the segment [a, b].
double DistanceToSegment(const Point& p, const Point& a, const Point& b);

/// Even-odd point-in-ring test (points on the boundary may go either way).
bool Contains(const Ring& ring, const Point& p);

}  // namespace rbcp::polygon2d
