// The support polygon of the feet in contact, in the ground plane (x, y), and how far a point is
// inside it: the same measure as the simulator's SupportPolygonMargin.

const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);

/** Convex hull of 2D points, counter-clockwise (Andrew's monotone chain). */
export function convexHull(points) {
  const sorted = [...points].sort((a, b) => a[0] - b[0] || a[1] - b[1]);
  if (sorted.length < 3) return sorted;
  const half = (list) => {
    const chain = [];
    for (const p of list) {
      while (chain.length >= 2 && cross(chain[chain.length - 2], chain[chain.length - 1], p) <= 0) chain.pop();
      chain.push(p);
    }
    chain.pop();
    return chain;
  };
  return [...half(sorted), ...half([...sorted].reverse())];
}

function segmentDistance(p, a, b) {
  const dx = b[0] - a[0];
  const dy = b[1] - a[1];
  const length2 = dx * dx + dy * dy;
  const s = length2 > 0 ? Math.min(Math.max(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2, 0), 1) : 0;
  return Math.hypot(p[0] - a[0] - s * dx, p[1] - a[1] - s * dy);
}

/** Signed distance [m] from p to the edge of the counter-clockwise convex polygon `hull`
 *  (positive inside); NaN for fewer than three corners. */
export function polygonMargin(hull, p) {
  if (hull.length < 3) return NaN;
  let distance = Infinity;
  let inside = true;
  hull.forEach((a, i) => {
    const b = hull[(i + 1) % hull.length];
    if (cross(a, b, p) < 0) inside = false;
    distance = Math.min(distance, segmentDistance(p, a, b));
  });
  return inside ? distance : -distance;
}
