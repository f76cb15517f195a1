#include "polygon_offset.h"

// Boost.Geometry 1.74 rescales coordinates to a 1e7 integer grid by default, which puts the
// offset boundary up to 1e-7 of the polygon's size off; work in plain doubles instead. Only
// this file includes Boost.Geometry.
#define BOOST_GEOMETRY_NO_ROBUSTNESS

#include <algorithm>
#include <boost/geometry.hpp>
#include <boost/geometry/geometries/multi_polygon.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>
#include <cmath>

namespace rbcp::polygon2d {
namespace {

namespace bg = boost::geometry;
using BoostPoint = bg::model::d2::point_xy<double>;
using BoostPolygon = bg::model::polygon<BoostPoint, /*ClockWise=*/false, /*Closed=*/true>;
using BoostMultiPolygon = bg::model::multi_polygon<BoostPolygon>;

/// Buffer join strategy: a round join whose arc is replaced by chords tangent to it (vertices
/// outside the circle), so the offset boundary never comes closer than the buffer distance to
/// the input. Same interface as bg::strategy::buffer::join_round.
class TangentRoundJoin {
 public:
  explicit TangentRoundJoin(int segments_per_circle) : max_step_(2.0 * M_PI / segments_per_circle) {}

  template <typename Point, typename DistanceType, typename RangeOut>
  bool apply(const Point& /*intersection*/, const Point& vertex, const Point& perp1, const Point& perp2,
             const DistanceType& buffer_distance, RangeOut& range_out) const {
    if (bg::equals(perp1, perp2)) return false;
    const double vx = bg::get<0>(vertex);
    const double vy = bg::get<1>(vertex);
    const double radius = std::abs(static_cast<double>(buffer_distance));
    const double angle1 = std::atan2(bg::get<1>(perp1) - vy, bg::get<0>(perp1) - vx);
    double angle2 = std::atan2(bg::get<1>(perp2) - vy, bg::get<0>(perp2) - vx);
    while (angle2 > angle1) angle2 -= 2.0 * M_PI;
    const double sweep = angle1 - angle2;
    const int n = std::max(1, static_cast<int>(std::ceil(sweep / max_step_ - 1e-9)));
    const double step = sweep / n;
    // The chord between two tangent points at angles a and a - step meets the circle's tangents
    // at radius / cos(step / 2).
    const double corner_radius = radius / std::cos(0.5 * step);
    range_out.push_back(perp1);
    for (int i = 0; i < n; ++i) {
      const double a = angle1 - (i + 0.5) * step;
      Point p;
      bg::set<0>(p, vx + corner_radius * std::cos(a));
      bg::set<1>(p, vy + corner_radius * std::sin(a));
      range_out.push_back(p);
    }
    range_out.push_back(perp2);
    return true;
  }

  template <typename NumericType>
  NumericType max_distance(const NumericType& distance) const {
    return distance / std::cos(0.5 * max_step_);
  }

 private:
  double max_step_;
};

void AppendRing(const Ring& ring, std::vector<BoostPoint>& out) {
  for (const Point& p : ring) out.emplace_back(p.x(), p.y());
  out.emplace_back(ring.front().x(), ring.front().y());
}

template <typename BoostRing>
Ring FromBoost(const BoostRing& ring) {
  Ring out;
  out.reserve(ring.size());
  for (const BoostPoint& p : ring) out.emplace_back(p.x(), p.y());
  if (out.size() > 1 && out.front() == out.back()) out.pop_back();
  RemoveCollinear(out);
  return out;
}

}  // namespace

bool Erode(const std::vector<PolygonWithHoles>& polygons, double margin, int arc_segments_per_circle,
           std::vector<PolygonWithHoles>& eroded) {
  eroded.clear();
  BoostMultiPolygon input;
  for (const PolygonWithHoles& polygon : polygons) {
    BoostPolygon p;
    AppendRing(polygon.outer, p.outer());
    for (const Ring& hole : polygon.holes) {
      p.inners().emplace_back();
      AppendRing(hole, p.inners().back());
    }
    input.push_back(std::move(p));
  }
  BoostMultiPolygon output;
  try {
    bg::buffer(input, output, bg::strategy::buffer::distance_symmetric<double>(-margin),
               bg::strategy::buffer::side_straight(), TangentRoundJoin(arc_segments_per_circle),
               bg::strategy::buffer::end_flat(), bg::strategy::buffer::point_circle(4));
  } catch (const bg::exception&) {
    return false;
  }
  for (const BoostPolygon& p : output) {
    PolygonWithHoles polygon;
    polygon.outer = FromBoost(p.outer());
    if (polygon.outer.size() < 3) continue;
    if (SignedArea(polygon.outer) < 0.0) std::reverse(polygon.outer.begin(), polygon.outer.end());
    for (const auto& inner : p.inners()) {
      Ring hole = FromBoost(inner);
      if (hole.size() < 3) continue;
      if (SignedArea(hole) > 0.0) std::reverse(hole.begin(), hole.end());
      polygon.holes.push_back(std::move(hole));
    }
    eroded.push_back(std::move(polygon));
  }
  return true;
}

}  // namespace rbcp::polygon2d
