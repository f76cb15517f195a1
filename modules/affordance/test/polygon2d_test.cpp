#include "polygon2d.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "polygon_offset.h"

namespace rbcp::polygon2d {
namespace {

Ring Rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

Ring Reversed(Ring r) {
  std::reverse(r.begin(), r.end());
  return r;
}

// L = [0, 2] x [0, 1] united with [0, 1] x [1, 2]; reflex corner at (1, 1).
Ring LShape(double s) { return {{0, 0}, {2 * s, 0}, {2 * s, s}, {s, s}, {s, 2 * s}, {0, 2 * s}}; }

double DistanceToBoundary(const PolygonWithHoles& p, const Point& q) {
  double d = std::numeric_limits<double>::infinity();
  const auto ring_distance = [&](const Ring& r) {
    for (std::size_t i = 0; i < r.size(); ++i) d = std::min(d, DistanceToSegment(q, r[i], r[(i + 1) % r.size()]));
  };
  ring_distance(p.outer);
  for (const Ring& h : p.holes) ring_distance(h);
  return d;
}

bool Inside(const PolygonWithHoles& p, const Point& q) {
  if (!Contains(p.outer, q)) return false;
  for (const Ring& h : p.holes) {
    if (Contains(h, q)) return false;
  }
  return true;
}

// Convex, counter-clockwise pieces that tile `polygon`: the areas add up, and grid points inside
// the polygon lie in exactly one piece, points outside in none.
void ExpectConvexTiling(const PolygonWithHoles& polygon, const std::vector<Ring>& pieces) {
  double area = 0.0;
  for (const Ring& piece : pieces) {
    EXPECT_TRUE(IsConvex(piece));
    EXPECT_GT(SignedArea(piece), 0.0);
    area += SignedArea(piece);
  }
  EXPECT_NEAR(area, Area(polygon), 1e-9);
  Eigen::AlignedBox2d box;
  for (const Point& p : polygon.outer) box.extend(p);
  const int n = 60;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      // Irrational offsets keep samples off edges and diagonals.
      const Point q = box.min() + Point((i + 0.5 + 0.0123 * std::sqrt(2.0)) / n * box.sizes().x(),
                                        (j + 0.5 + 0.0171 * std::sqrt(3.0)) / n * box.sizes().y());
      int in_pieces = 0;
      for (const Ring& piece : pieces) in_pieces += Contains(piece, q) ? 1 : 0;
      EXPECT_EQ(in_pieces, Inside(polygon, q) ? 1 : 0) << "at " << q.transpose();
    }
  }
}

TEST(Polygon2d, SignedAreaFollowsOrientation) {
  EXPECT_DOUBLE_EQ(SignedArea(Rect(0, 0, 2, 3)), 6.0);
  EXPECT_DOUBLE_EQ(SignedArea(Reversed(Rect(0, 0, 2, 3))), -6.0);
  EXPECT_DOUBLE_EQ(Area(PolygonWithHoles{Rect(0, 0, 4, 4), {Reversed(Rect(1, 1, 2, 2))}}), 15.0);
}

TEST(Polygon2d, RemoveCollinearDropsStraightRepeatedAndSpikeVertices) {
  Ring r = {{0, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {1, 3}, {1, 2}, {0, 2}, {0, 1}};
  RemoveCollinear(r);
  EXPECT_EQ(r, Ring({{0, 0}, {2, 0}, {2, 2}, {0, 2}}));
  // A straight vertex at the seam (first and last positions) goes too.
  Ring seam = {{1, 0}, {2, 0}, {2, 2}, {0, 2}, {0, 0}};
  RemoveCollinear(seam);
  EXPECT_EQ(seam, Ring({{2, 0}, {2, 2}, {0, 2}, {0, 0}}));
  Ring flat = {{0, 0}, {1, 0}, {2, 0}};
  RemoveCollinear(flat);
  EXPECT_TRUE(flat.empty());
  Ring kept = {{0, 0}, {1, 1e-6}, {2, 0}, {1, 1}};
  RemoveCollinear(kept);
  EXPECT_EQ(kept.size(), 4u);
}

TEST(Polygon2d, ConvexityNeedsLeftTurnsAndOneWinding) {
  EXPECT_TRUE(IsConvex(Rect(0, 0, 1, 1)));
  EXPECT_FALSE(IsConvex(Reversed(Rect(0, 0, 1, 1))));
  EXPECT_FALSE(IsConvex(LShape(1.0)));
  Ring star;
  for (int i = 0; i < 5; ++i) {
    const double a = 2.0 * M_PI * (2 * i) / 5.0;
    star.emplace_back(std::cos(a), std::sin(a));
  }
  EXPECT_FALSE(IsConvex(star)) << "a pentagram turns left everywhere but winds twice";
}

TEST(Polygon2d, ConvexErosionIsExactForRectanglesAndTriangles) {
  Ring out, scratch;
  ErodeConvex(Rect(-1.0, -0.5, 1.0, 0.5), 0.1, out, scratch);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_NEAR(SignedArea(out), 1.8 * 0.8, 1e-12);
  for (const Point& p : out) {
    EXPECT_NEAR(std::abs(p.x()), 0.9, 1e-12);
    EXPECT_NEAR(std::abs(p.y()), 0.4, 1e-12);
  }
  // A 3-4-5 triangle has inradius 1; erosion by m leaves a similar triangle scaled by (1 - m).
  const Ring tri = {{0, 0}, {4, 0}, {0, 3}};
  ErodeConvex(tri, 0.25, out, scratch);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_NEAR(SignedArea(out), 6.0 * 0.75 * 0.75, 1e-12);
  for (const Point& p : out) {
    double d = 1e9;
    for (int i = 0; i < 3; ++i)
      d = std::min(d,
                   DistanceToSegment(p, tri[static_cast<std::size_t>(i)], tri[static_cast<std::size_t>((i + 1) % 3)]));
    EXPECT_NEAR(d, 0.25, 1e-12);
  }
  ErodeConvex(tri, 1.0 + 1e-9, out, scratch);
  EXPECT_TRUE(out.empty());
  ErodeConvex(tri, 0.0, out, scratch);
  EXPECT_EQ(out, tri);
}

TEST(Polygon2d, PartitionOfAnLShapeIsTwoConvexPieces) {
  const PolygonWithHoles l{LShape(1.0), {}};
  std::vector<Ring> pieces;
  ASSERT_TRUE(ConvexPartition(l, pieces));
  EXPECT_EQ(pieces.size(), 2u);
  ExpectConvexTiling(l, pieces);
}

TEST(Polygon2d, PartitionHandlesHoles) {
  const PolygonWithHoles frame{Rect(0, 0, 1, 1), {Reversed(Rect(0.3, 0.3, 0.7, 0.7))}};
  std::vector<Ring> pieces;
  ASSERT_TRUE(ConvexPartition(frame, pieces));
  EXPECT_GE(pieces.size(), 4u);
  EXPECT_LE(pieces.size(), 8u);
  ExpectConvexTiling(frame, pieces);

  const PolygonWithHoles two_holes{Rect(0, 0, 3, 1),
                                   {Reversed(Rect(0.5, 0.25, 1.0, 0.75)), Reversed(Rect(2.0, 0.4, 2.5, 0.6))}};
  ASSERT_TRUE(ConvexPartition(two_holes, pieces));
  ExpectConvexTiling(two_holes, pieces);

  // A hole touching the outer ring at the vertex (2, 2).
  const PolygonWithHoles touching{{{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 3}, {0, 3}}, {Reversed(Rect(1, 1, 2, 2))}};
  ASSERT_TRUE(ConvexPartition(touching, pieces));
  ExpectConvexTiling(touching, pieces);
}

TEST(Polygon2d, PartitionOfAComb) {
  // Teeth pointing up: every gap between teeth makes two reflex corners.
  Ring comb = {{0, 0}, {5, 0}, {5, 2}};
  for (int i = 4; i >= 0; --i) {
    comb.emplace_back(i + 0.6, 2);
    comb.emplace_back(i + 0.6, 1);
    comb.emplace_back(i + 0.4, 1);
    comb.emplace_back(i + 0.4, 2);
  }
  comb.emplace_back(0, 2);
  RemoveCollinear(comb);
  const PolygonWithHoles polygon{comb, {}};
  std::vector<Ring> pieces;
  ASSERT_TRUE(ConvexPartition(polygon, pieces));
  // Hertel-Mehlhorn: at most 2r + 1 pieces for r reflex vertices (here 10).
  EXPECT_LE(pieces.size(), 21u);
  ExpectConvexTiling(polygon, pieces);
}

TEST(Polygon2d, PartitionOfAStarShapedPolygon) {
  Ring star;
  for (int i = 0; i < 14; ++i) {
    const double a = 2.0 * M_PI * i / 14.0;
    const double r = (i % 2 == 0) ? 1.0 : 0.45;
    star.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  const PolygonWithHoles polygon{star, {}};
  std::vector<Ring> pieces;
  ASSERT_TRUE(ConvexPartition(polygon, pieces));
  ExpectConvexTiling(polygon, pieces);
}

// Area of the exact erosion of a polygon minus what the tangent chords of the arcs miss:
// per arc of sweep s split in n chords, m^2 (n tan(s / 2n) - s / 2).
double ArcLoss(double m, double sweep) {
  const int n = static_cast<int>(std::ceil(sweep / (2.0 * M_PI / 16) - 1e-9));
  return m * m * (n * std::tan(sweep / (2.0 * n)) - 0.5 * sweep);
}

TEST(Polygon2d, ErosionOfAnLShapeMatchesTheExactOffset) {
  const double s = 1.0;
  const double m = 0.1;
  const PolygonWithHoles l{LShape(s), {}};
  std::vector<PolygonWithHoles> eroded;
  ASSERT_TRUE(Erode({l}, m, 16, eroded));
  ASSERT_EQ(eroded.size(), 1u);
  // Two shrunken arms plus the corner square at the reflex vertex minus its quarter disc.
  const double arms = 2.0 * (2 * s - 2 * m) * (s - 2 * m) - (s - 2 * m) * (s - 2 * m);
  const double exact = arms + m * m - 0.25 * M_PI * m * m;
  EXPECT_NEAR(Area(eroded[0]), exact - ArcLoss(m, 0.5 * M_PI), 1e-9);
  EXPECT_TRUE(eroded[0].holes.empty());
  // Every vertex is at least m from the boundary, and never inside the disc around the reflex corner.
  for (const Point& p : eroded[0].outer) {
    EXPECT_GE(DistanceToBoundary(l, p), m - 1e-9);
    EXPECT_TRUE(Inside(l, p));
  }
}

TEST(Polygon2d, ErosionOfAFrameGrowsTheHoleWithRoundCorners) {
  const double m = 0.05;
  const PolygonWithHoles frame{Rect(0, 0, 1, 1), {Reversed(Rect(0.3, 0.3, 0.7, 0.7))}};
  std::vector<PolygonWithHoles> eroded;
  ASSERT_TRUE(Erode({frame}, m, 16, eroded));
  ASSERT_EQ(eroded.size(), 1u);
  ASSERT_EQ(eroded[0].holes.size(), 1u);
  const double hole = 0.4 * 0.4 + 4 * 0.4 * m + M_PI * m * m + 4 * ArcLoss(m, 0.5 * M_PI);
  EXPECT_NEAR(Area(eroded[0]), 0.9 * 0.9 - hole, 1e-9);
  for (const Point& p : eroded[0].holes[0]) EXPECT_GE(DistanceToBoundary(frame, p), m - 1e-9);
}

TEST(Polygon2d, ErosionSplitsADumbbellAndRemovesThinParts) {
  // Two 1 x 1 squares joined by a 0.1 m wide neck: eroding by 0.06 cuts the neck.
  const Ring dumbbell = {{0, 0}, {1, 0}, {1, 0.45}, {2, 0.45}, {2, 0}, {3, 0},
                         {3, 1}, {2, 1}, {2, 0.55}, {1, 0.55}, {1, 1}, {0, 1}};
  std::vector<PolygonWithHoles> eroded;
  ASSERT_TRUE(Erode({PolygonWithHoles{dumbbell, {}}}, 0.06, 16, eroded));
  ASSERT_EQ(eroded.size(), 2u);
  // Each square shrinks to 0.88 x 0.88 plus a small cusp towards the neck, between the arcs
  // around the neck's corners, which reach at most sqrt(0.06^2 - 0.05^2) = 0.033 m further.
  for (const auto& p : eroded) {
    EXPECT_GT(Area(p), 0.88 * 0.88);
    EXPECT_LT(Area(p), 0.88 * 0.88 + 0.034 * 0.1);
  }
  ASSERT_TRUE(Erode({PolygonWithHoles{Rect(0, 0, 1, 0.1), {}}}, 0.06, 16, eroded));
  EXPECT_TRUE(eroded.empty());
}

}  // namespace
}  // namespace rbcp::polygon2d
