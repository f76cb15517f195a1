#pragma once
/// Inward offset (Minkowski erosion) of general plane polygons.

#include <vector>

#include "polygon2d.h"

namespace rbcp::polygon2d {

/// Erodes disjoint polygons (outer counter-clockwise, holes clockwise) by `margin` > 0: what is
/// left is every point of the input at least `margin` from its boundary. Straight parts of the
/// offset are exact; the arc around each reflex corner is replaced by chords tangent to it, at
/// most 2 pi / `arc_segments_per_circle` of arc each, so the result lies inside the exact erosion
/// and misses at most margin^2 (n tan(pi / n) - pi) per full turn of arcs, n the segment count.
/// The result may split into several polygons or be empty; rings come back cleaned
/// (RemoveCollinear) with the same orientation conventions. Returns false, with `eroded` empty,
/// if the offset could not be computed (self-intersecting input).
bool Erode(const std::vector<PolygonWithHoles>& polygons, double margin, int arc_segments_per_circle,
           std::vector<PolygonWithHoles>& eroded);

}  // namespace rbcp::polygon2d
