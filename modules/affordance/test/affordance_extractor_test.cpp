#include "rbcp/affordance/affordance_extractor.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <utility>

#include "polygon2d.h"
#include "rbcp/core/pose.h"

namespace rbcp {
namespace {

using polygon2d::Point;
using polygon2d::Ring;

constexpr double kDeg = M_PI / 180.0;

TriangleMesh Box(const Eigen::Vector3d& size, const Eigen::Vector3d& centre,
                 const Eigen::Vector3d& rpy = Eigen::Vector3d::Zero()) {
  TriangleMesh m = MakeBoxMesh(size);
  m.Transform(PoseFromRpy(centre, rpy));
  return m;
}

AffordanceConfig Config(double edge_margin, double min_area = 0.5e-4) {
  AffordanceConfig c;
  c.edge_margin = edge_margin;
  c.min_area = min_area;
  return c;
}

/// Flat square cells of side `size` at height z, sharing vertices on a lattice, counter-clockwise
/// seen from above. Cell (i, j) covers [i, i + 1] x [j, j + 1] * size.
TriangleMesh Cells(const std::vector<std::pair<int, int>>& cells, double size, double z) {
  TriangleMesh m;
  std::map<std::pair<int, int>, int> index;
  const auto vertex = [&](int i, int j) {
    auto [it, inserted] = index.try_emplace({i, j}, static_cast<int>(m.vertices.size()));
    if (inserted) m.vertices.emplace_back(i * size, j * size, z);
    return it->second;
  };
  for (const auto& [i, j] : cells) {
    const int a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  }
  return m;
}

/// The same triangles with three private vertices each, in a scrambled triangle order.
TriangleMesh Soup(const TriangleMesh& mesh) {
  TriangleMesh soup;
  const std::size_t n = mesh.triangles.size();
  std::size_t stride = 7;  // coprime with n, so k -> (k * stride + 3) % n visits every triangle
  while (std::gcd(stride, n) != 1) ++stride;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t t = (k * stride + 3) % n;
    const int base = static_cast<int>(soup.vertices.size());
    for (int c = 0; c < 3; ++c) soup.vertices.push_back(mesh.Corner(t, c));
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  return soup;
}

Point Xy(const Eigen::Vector3d& p) { return {p.x(), p.y()}; }

Ring XyRing(const AffordanceSurface& s) {
  Ring r;
  for (const auto& v : s.vertices) r.push_back(Xy(v));
  return r;
}

/// A flat region given as a union of grid cells: distance to its boundary and inside test.
struct CellRegion {
  std::set<std::pair<int, int>> cells;
  double size;
  std::vector<std::pair<Point, Point>> boundary;

  CellRegion(const std::vector<std::pair<int, int>>& list, double s) : cells(list.begin(), list.end()), size(s) {
    for (const auto& [i, j] : cells) {
      const Point p00(i * s, j * s), p10((i + 1) * s, j * s), p11((i + 1) * s, (j + 1) * s), p01(i * s, (j + 1) * s);
      if (!cells.count({i, j - 1})) boundary.emplace_back(p00, p10);
      if (!cells.count({i + 1, j})) boundary.emplace_back(p10, p11);
      if (!cells.count({i, j + 1})) boundary.emplace_back(p11, p01);
      if (!cells.count({i - 1, j})) boundary.emplace_back(p01, p00);
    }
  }
  double Distance(const Point& p) const {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : boundary) d = std::min(d, polygon2d::DistanceToSegment(p, a, b));
    return d;
  }
  bool Inside(const Point& p) const {
    return cells.count({static_cast<int>(std::floor(p.x() / size)), static_cast<int>(std::floor(p.y() / size))}) > 0;
  }
};

/// Checks flat surfaces against the exact erosion of `region` by m: each is convex and
/// counter-clockwise seen from +z; every point of every edge is inside the region and at least m
/// from its boundary; grid points clearly inside the erosion are covered by exactly one surface,
/// points closer than m to the boundary by none.
void ExpectEroded(const std::vector<AffordanceSurface>& surfaces, const CellRegion& region, double m, double z,
                  int samples = 80) {
  const double arc_slack = m * (1.0 / std::cos(M_PI / kErosionArcSegmentsPerCircle) - 1.0) + 1e-6;
  for (const auto& s : surfaces) {
    const Ring r = XyRing(s);
    EXPECT_TRUE(polygon2d::IsConvex(r));
    EXPECT_NEAR(polygon2d::SignedArea(r), s.area, 1e-12);
    EXPECT_NEAR(s.normal.z(), 1.0, 1e-12);
    for (std::size_t i = 0; i < r.size(); ++i) {
      EXPECT_NEAR(s.vertices[i].z(), z, 1e-9);
      for (int k = 0; k <= 20; ++k) {
        const Point p = r[i] + (k / 20.0) * (r[(i + 1) % r.size()] - r[i]);
        EXPECT_TRUE(region.Inside(p) || region.Distance(p) <= 1e-9) << p.transpose();
        EXPECT_GE(region.Distance(p), m - 1e-9) << p.transpose();
      }
    }
  }
  Eigen::AlignedBox2d box;
  for (const auto& [i, j] : region.cells) {
    box.extend(Point(i * region.size, j * region.size));
    box.extend(Point((i + 1) * region.size, (j + 1) * region.size));
  }
  const int n = samples;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Point q = box.min() + Point((i + 0.5 + 0.01 * std::sqrt(2.0)) / n * box.sizes().x(),
                                        (j + 0.5 + 0.01 * std::sqrt(3.0)) / n * box.sizes().y());
      int covered = 0;
      for (const auto& s : surfaces) covered += polygon2d::Contains(XyRing(s), q) ? 1 : 0;
      const double d = region.Inside(q) ? region.Distance(q) : -1.0;
      if (d > m + arc_slack) {
        EXPECT_EQ(covered, 1) << "at " << q.transpose() << ", " << d << " m from the boundary";
      } else if (d < m - 1e-9) {
        EXPECT_EQ(covered, 0) << "at " << q.transpose() << ", " << d << " m from the boundary";
      } else {
        EXPECT_LE(covered, 1);
      }
    }
  }
}

/// Area the tangent chords of an arc of `sweep` rad and radius m cut off the exact erosion.
double ArcLoss(double m, double sweep) {
  const double step = 2.0 * M_PI / kErosionArcSegmentsPerCircle;
  const int n = static_cast<int>(std::ceil(sweep / step - 1e-9));
  return m * m * (n * std::tan(sweep / (2.0 * n)) - 0.5 * sweep);
}

double TotalArea(const std::vector<AffordanceSurface>& surfaces) {
  double a = 0.0;
  for (const auto& s : surfaces) a += s.area;
  return a;
}

TEST(AffordanceExtractor, FlatBoxGivesItsExactlyErodedTop) {
  const double m = 0.04;
  AffordanceExtractor extractor(Config(m));
  const auto surfaces = extractor.Extract(Box({2.0, 1.0, 0.2}, {0.5, -0.2, 0.2}));
  ASSERT_EQ(surfaces.size(), 1u);
  const AffordanceSurface& s = surfaces[0];
  EXPECT_EQ(s.normal, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(s.area, (2.0 - 2 * m) * (1.0 - 2 * m), 1e-12);
  ASSERT_EQ(s.vertices.size(), 4u);
  std::set<std::pair<int, int>> corners;
  for (const auto& v : s.vertices) {
    EXPECT_NEAR(v.z(), 0.3, 1e-12);
    const double dx = v.x() - 0.5, dy = v.y() + 0.2;
    EXPECT_NEAR(std::abs(dx), 1.0 - m, 1e-12);
    EXPECT_NEAR(std::abs(dy), 0.5 - m, 1e-12);
    corners.insert({dx > 0 ? 1 : -1, dy > 0 ? 1 : -1});
  }
  EXPECT_EQ(corners.size(), 4u);
  EXPECT_GT(polygon2d::SignedArea(XyRing(s)), 0.0) << "counter-clockwise seen from above";
  EXPECT_EQ(extractor.stats().triangles, 12);
  EXPECT_EQ(extractor.stats().candidate_triangles, 2);
  EXPECT_EQ(extractor.stats().planar_regions, 1);
  EXPECT_EQ(extractor.stats().convex_regions, 1);
  EXPECT_EQ(extractor.stats().surfaces, 1);
}

TEST(AffordanceExtractor, ZeroMarginKeepsTheWholeTop) {
  AffordanceExtractor extractor(Config(0.0));
  const auto surfaces = extractor.Extract(Box({2.0, 1.0, 0.2}, {0, 0, -0.1}));
  ASSERT_EQ(surfaces.size(), 1u);
  EXPECT_NEAR(surfaces[0].area, 2.0, 1e-12);
  EXPECT_EQ(surfaces[0].vertices.size(), 4u);
}

TEST(AffordanceExtractor, BlockTopTilted15DegreesPasses) {
  const double m = 0.04;
  AffordanceExtractor extractor(Config(m));
  const Eigen::Vector3d centre(1.0, 2.0, 0.2);
  const auto surfaces = extractor.Extract(Box({0.30, 0.21, 0.1}, centre, {0.0, 15 * kDeg, 0.0}));
  ASSERT_EQ(surfaces.size(), 1u);
  const AffordanceSurface& s = surfaces[0];
  EXPECT_TRUE(s.normal.isApprox(Eigen::Vector3d(std::sin(15 * kDeg), 0, std::cos(15 * kDeg)), 1e-12));
  EXPECT_NEAR(s.area, (0.30 - 2 * m) * (0.21 - 2 * m), 1e-12);
  // On the top plane, counter-clockwise about the normal.
  const double offset = s.normal.dot(centre) + 0.05;
  Eigen::Vector3d twice_area = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    EXPECT_NEAR(s.normal.dot(s.vertices[i]), offset, 1e-12);
    twice_area += s.vertices[i].cross(s.vertices[(i + 1) % s.vertices.size()]);
  }
  EXPECT_NEAR(0.5 * twice_area.dot(s.normal), s.area, 1e-12);
}

TEST(AffordanceExtractor, InclinationLimitSeparates40From45Degrees) {
  AffordanceExtractor extractor(Config(0.04));
  EXPECT_EQ(extractor.Extract(Box({1, 1, 0.1}, {0, 0, 0}, {0, 40 * kDeg, 0})).size(), 1u);
  EXPECT_TRUE(extractor.Extract(Box({1, 1, 0.1}, {0, 0, 0}, {0, 45 * kDeg, 0})).empty());
  EXPECT_EQ(extractor.stats().candidate_triangles, 0);
  EXPECT_TRUE(extractor.Extract(Box({1, 1, 0.1}, {0, 0, 0}, {45 * kDeg, 0, 0})).empty());
}

TEST(AffordanceExtractor, WallsAndDownwardFacesAreNeverSupport) {
  AffordanceExtractor extractor(Config(0.0, 0.0));
  TriangleMesh wall;
  wall.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  wall.triangles = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_TRUE(extractor.Extract(wall).empty());
  EXPECT_EQ(extractor.stats().candidate_triangles, 0);

  TriangleMesh ceiling;  // a horizontal square wound clockwise seen from above: it faces down
  ceiling.vertices = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  ceiling.triangles = {{0, 2, 1}, {0, 3, 2}};
  EXPECT_TRUE(extractor.Extract(ceiling).empty());
  EXPECT_EQ(extractor.stats().candidate_triangles, 0);

  // Of a box only the top supports; its bottom faces down and its sides are walls.
  EXPECT_EQ(extractor.Extract(Box({1, 1, 1}, {0, 0, 0})).size(), 1u);
  EXPECT_EQ(extractor.stats().candidate_triangles, 2);
}

TEST(AffordanceExtractor, SurfacesAtOrBelowMinAreaAreDropped) {
  AffordanceExtractor no_margin(Config(0.0, 0.5e-4));
  EXPECT_TRUE(no_margin.Extract(Box({0.005, 0.005, 0.01}, {0, 0, 0})).empty()) << "0.25 cm^2";
  EXPECT_EQ(no_margin.stats().planar_regions, 1);
  EXPECT_EQ(no_margin.stats().kept_regions, 0);
  EXPECT_EQ(no_margin.Extract(Box({0.01, 0.01, 0.01}, {0, 0, 0})).size(), 1u) << "1 cm^2";

  // After erosion: 0.086 m - 2 * 0.04 m leaves 0.36 cm^2, 0.09 m leaves 1 cm^2.
  AffordanceExtractor eroding(Config(0.04, 0.5e-4));
  EXPECT_TRUE(eroding.Extract(Box({0.086, 0.086, 0.01}, {0, 0, 0})).empty());
  EXPECT_EQ(eroding.stats().vanished_regions, 1);
  const auto kept = eroding.Extract(Box({0.09, 0.09, 0.01}, {0, 0, 0}));
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_NEAR(kept[0].area, 1e-4, 1e-15);
}

TEST(AffordanceExtractor, StripNarrowerThanTwiceTheMarginVanishes) {
  AffordanceExtractor extractor(Config(0.04));
  EXPECT_TRUE(extractor.Extract(Box({2.0, 0.079, 0.1}, {0, 0, 0})).empty());
  EXPECT_EQ(extractor.stats().kept_regions, 1);
  EXPECT_EQ(extractor.stats().vanished_regions, 1);
  const auto kept = extractor.Extract(Box({2.0, 0.082, 0.1}, {0, 0, 0}));
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_NEAR(kept[0].area, 1.92 * 0.002, 1e-12);
}

TEST(AffordanceExtractor, LShapedRegionBecomesConvexPiecesOfTheExactErosion) {
  const double m = 0.04, s = 0.5, z = 0.1;
  const std::vector<std::pair<int, int>> cells = {{0, 0}, {1, 0}, {0, 1}};
  AffordanceExtractor extractor(Config(m));
  const auto surfaces = extractor.Extract(Cells(cells, s, z));
  EXPECT_EQ(extractor.stats().planar_regions, 1);
  EXPECT_EQ(extractor.stats().convex_regions, 0);
  ASSERT_GE(surfaces.size(), 2u);
  // Exact erosion of L = [0, 2s] x [0, s] + [0, s] x [s, 2s]: two shrunken arms, plus the square
  // at the reflex corner (s, s) minus the quarter disc of radius m around it.
  const double arms = 2.0 * (2 * s - 2 * m) * (s - 2 * m) - (s - 2 * m) * (s - 2 * m);
  const double exact = arms + m * m * (1.0 - 0.25 * M_PI);
  const double loss = ArcLoss(m, 0.5 * M_PI);
  EXPECT_NEAR(TotalArea(surfaces), exact - loss, 1e-9);
  EXPECT_LT(loss, 1e-4 * exact) << "round-join approximation tolerance";
  ExpectEroded(surfaces, CellRegion(cells, s), m, z);
}

TEST(AffordanceExtractor, TriangleSoupIsWeldedIntoTheSameSurfaces) {
  const std::vector<std::pair<int, int>> cells = {{0, 0}, {1, 0}, {0, 1}};
  AffordanceExtractor extractor(Config(0.04));
  const TriangleMesh indexed = Cells(cells, 0.5, 0.0);
  const auto a = extractor.Extract(indexed);
  const auto b = extractor.Extract(Soup(indexed));
  EXPECT_EQ(extractor.stats().welded_vertices, 8);
  EXPECT_EQ(extractor.stats().planar_regions, 1);
  EXPECT_NEAR(TotalArea(a), TotalArea(b), 1e-12);
  ExpectEroded(b, CellRegion(cells, 0.5), 0.04, 0.0);

  // Jitter far below the weld tolerance still welds.
  TriangleMesh jittered = Soup(indexed);
  for (auto& v : jittered.vertices)
    v.x() += 1e-8 * std::sin(100.0 * v.y() + 10.0 * v.x() + 3.0 * (&v - &jittered.vertices[0]));
  extractor.Extract(jittered);
  EXPECT_EQ(extractor.stats().planar_regions, 1);
  // A gap above it does not: cell (1, 0) moved 2 um along x becomes its own region.
  TriangleMesh gap = Soup(indexed);
  for (std::size_t t = 0; t < gap.NumTriangles(); ++t) {
    if ((gap.Corner(t, 0) + gap.Corner(t, 1) + gap.Corner(t, 2)).x() / 3.0 > 0.5) {
      for (int idx : gap.triangles[t]) gap.vertices[static_cast<std::size_t>(idx)].x() += 2e-6;
    }
  }
  extractor.Extract(gap);
  EXPECT_EQ(extractor.stats().planar_regions, 2);
}

TEST(AffordanceExtractor, ABoxListedManyTimesIsOneBox) {
  AffordanceExtractor extractor(Config(0.04));
  const TriangleMesh box = Box({1.0, 0.6, 0.2}, {0.0, 0.0, -0.1});
  const auto once = extractor.Extract(box);
  ASSERT_EQ(once.size(), 1u);
  TriangleMesh many;
  for (int copy = 0; copy < 50; ++copy) {
    // Every other copy lists each triangle from another corner: still the same triangle.
    TriangleMesh c = box;
    if (copy % 2 == 1) {
      for (auto& t : c.triangles) std::rotate(t.begin(), t.begin() + 1, t.end());
    }
    many.Append(c);
  }
  const auto surfaces = extractor.Extract(many);
  EXPECT_EQ(extractor.stats().duplicate_triangles, 49 * 2) << "the top's two triangles, 49 times again";
  ASSERT_EQ(surfaces.size(), 1u) << "one surface, not fifty";
  EXPECT_EQ(surfaces[0].vertices, once[0].vertices);
}

TEST(AffordanceExtractor, FloorMadeOfManyTrianglesIsOneRectangle) {
  std::vector<std::pair<int, int>> cells;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 4; ++j) cells.emplace_back(i, j);
  }
  AffordanceExtractor extractor(Config(0.04));
  const auto surfaces = extractor.Extract(Soup(Cells(cells, 0.25, 0.0)));
  ASSERT_EQ(surfaces.size(), 1u);
  EXPECT_EQ(surfaces[0].vertices.size(), 4u);
  EXPECT_NEAR(surfaces[0].area, (1.5 - 0.08) * (1.0 - 0.08), 1e-12);
  EXPECT_EQ(extractor.stats().convex_regions, 1);
}

TEST(AffordanceExtractor, FrameRegionErodesAroundItsHole) {
  const double m = 0.04, s = 1.0 / 3.0;
  std::vector<std::pair<int, int>> cells;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (i != 1 || j != 1) cells.emplace_back(i, j);
    }
  }
  AffordanceExtractor extractor(Config(m));
  const auto surfaces = extractor.Extract(Cells(cells, s, 0.0));
  EXPECT_EQ(extractor.stats().planar_regions, 1);
  ASSERT_GE(surfaces.size(), 4u);
  const double grown_hole = s * s + 4 * s * m + M_PI * m * m + 4 * ArcLoss(m, 0.5 * M_PI);
  EXPECT_NEAR(TotalArea(surfaces), (1 - 2 * m) * (1 - 2 * m) - grown_hole, 1e-9);
  ExpectEroded(surfaces, CellRegion(cells, s), m, 0.0);
}

TEST(AffordanceExtractor, HoleTouchingTheOuterBoundaryAtAVertex) {
  // A frame with its corner cell (2, 2) missing: the hole (1, 1) and the outside meet at one vertex.
  const double m = 0.04, s = 0.3;
  const std::vector<std::pair<int, int>> cells = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {2, 1}, {0, 2}, {1, 2}};
  AffordanceExtractor extractor(Config(m));
  const auto surfaces = extractor.Extract(Cells(cells, s, 0.5));
  EXPECT_EQ(extractor.stats().planar_regions, 1);
  EXPECT_EQ(extractor.stats().geometry_failures, 0);
  ASSERT_FALSE(surfaces.empty());
  ExpectEroded(surfaces, CellRegion(cells, s), m, 0.5);
  // Without erosion the pinched region itself is split into convex pieces.
  AffordanceExtractor exact(Config(0.0));
  const auto pieces = exact.Extract(Cells(cells, s, 0.5));
  EXPECT_EQ(exact.stats().geometry_failures, 0);
  EXPECT_NEAR(TotalArea(pieces), 7 * s * s, 1e-12);
  ExpectEroded(pieces, CellRegion(cells, s), 0.0, 0.5);
}

TEST(AffordanceExtractor, RandomCellRegionsMatchTheExactErosion) {
  // Random 6 x 6 patterns of 0.2 m cells (non-convex regions, holes, pinched vertices) as
  // triangle soups, placed with a random pose tilted up to 20 degrees; the surfaces are brought
  // back to the pattern's frame and checked against the exact erosion.
  std::mt19937 rng(7);
  const auto uniform = [&rng](double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(rng() % 10000) / 10000.0;
  };
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<std::pair<int, int>> cells;
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        if (static_cast<int>(rng() % 100) < 45 + trial) cells.emplace_back(i, j);
      }
    }
    if (cells.empty()) continue;
    const double m = 0.01 + 0.01 * static_cast<double>(rng() % 8);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = RotationFromRpy({uniform(-0.35, 0.35), uniform(-0.35, 0.35), uniform(-M_PI, M_PI)});
    pose.translation() = Eigen::Vector3d(uniform(-5, 5), uniform(-5, 5), uniform(-1, 1));
    TriangleMesh mesh = Soup(Cells(cells, 0.2, 0.0));
    mesh.Transform(pose);

    AffordanceExtractor extractor(Config(m, 0.0));
    auto surfaces = extractor.Extract(mesh);
    SCOPED_TRACE("trial " + std::to_string(trial) + ", margin " + std::to_string(m));
    EXPECT_EQ(extractor.stats().geometry_failures, 0);
    for (auto& s : surfaces) {
      EXPECT_TRUE(s.normal.isApprox(pose.linear().col(2), 1e-12));
      for (auto& v : s.vertices) v = pose.inverse() * v;
      s.normal = pose.linear().transpose() * s.normal;
    }
    ExpectEroded(surfaces, CellRegion(cells, 0.2), m, 0.0, 48);
  }
}

TEST(AffordanceExtractor, EqualBoxesSideBySideMergeWhereTheirCornersCoincide) {
  const double m = 0.04;
  AffordanceExtractor extractor(Config(m));
  TriangleMesh two = Box({1.0, 0.5, 0.2}, {0.5, 0, -0.1});
  two.Append(Box({1.0, 0.5, 0.2}, {1.5, 0, -0.1}));
  const auto merged = extractor.Extract(two);
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_NEAR(merged[0].area, (2.0 - 2 * m) * (0.5 - 2 * m), 1e-12);
  EXPECT_EQ(merged[0].vertices.size(), 4u);
}

TEST(AffordanceExtractor, TouchingBoxesWithoutSharedCornersStaySeparate) {
  // The second box is narrower: its top meets the first along a T-junction, no shared edge.
  const double m = 0.04;
  AffordanceExtractor extractor(Config(m));
  TriangleMesh two = Box({1.0, 0.5, 0.2}, {0.5, 0, -0.1});
  two.Append(Box({1.0, 0.3, 0.2}, {1.5, 0, -0.1}));
  const auto surfaces = extractor.Extract(two);
  ASSERT_EQ(surfaces.size(), 2u);
  EXPECT_NEAR(surfaces[0].area, (1.0 - 2 * m) * (0.5 - 2 * m), 1e-12);
  EXPECT_NEAR(surfaces[1].area, (1.0 - 2 * m) * (0.3 - 2 * m), 1e-12);
}

TEST(AffordanceExtractor, SmallStepSeparatesParallelSurfaces) {
  // Two 1 m squares, the second 5 mm higher, joined by a vertical riser sharing their edges.
  TriangleMesh step;
  step.vertices = {{0, 0, 0},     {1, 0, 0},     {1, 1, 0},     {0, 1, 0},
                   {1, 0, 0.005}, {2, 0, 0.005}, {2, 1, 0.005}, {1, 1, 0.005}};
  step.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {1, 4, 7}, {1, 7, 2}};
  AffordanceExtractor extractor(Config(0.04));
  const auto surfaces = extractor.Extract(step);
  EXPECT_EQ(extractor.stats().candidate_triangles, 4);
  EXPECT_EQ(extractor.stats().planar_regions, 2);
  ASSERT_EQ(surfaces.size(), 2u);
  EXPECT_NEAR(surfaces[0].vertices[0].z(), 0.0, 1e-12);
  EXPECT_NEAR(surfaces[1].vertices[0].z(), 0.005, 1e-12);
}

/// Two w x w squares sharing the edge x = 0; the second rises at `fold_deg` towards +x.
TriangleMesh Fold(double w, double fold_deg) {
  const double c = std::cos(fold_deg * kDeg), s = std::sin(fold_deg * kDeg);
  TriangleMesh m;
  m.vertices = {{-w, 0, 0}, {0, 0, 0}, {0, w, 0}, {-w, w, 0}, {w * c, 0, w * s}, {w * c, w, w * s}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  return m;
}

TEST(AffordanceExtractor, FoldOf10DegreesAcrossASharedEdgeSplits) {
  AffordanceExtractor extractor(Config(0.0, 0.0));
  extractor.Extract(Fold(1.0, 10.0));
  EXPECT_EQ(extractor.stats().planar_regions, 2);
  // 3 mm squares stay within 1 mm of each other's plane, so only the normal test decides.
  extractor.Extract(Fold(0.003, 10.0));
  EXPECT_EQ(extractor.stats().planar_regions, 2);
  extractor.Extract(Fold(0.003, 8.0));
  EXPECT_EQ(extractor.stats().planar_regions, 1);
}

TEST(AffordanceExtractor, NormalsWithinTheNeighbourAngleButNotCoplanarAreSeparate) {
  // A 2 degree fold of 1 m squares: the far edge is 35 mm off the seed plane.
  AffordanceExtractor extractor(Config(0.0, 0.0));
  extractor.Extract(Fold(1.0, 2.0));
  EXPECT_EQ(extractor.stats().planar_regions, 2);
  // The same fold 2 cm wide stays within the coplanarity tolerance (0.7 mm).
  extractor.Extract(Fold(0.02, 2.0));
  EXPECT_EQ(extractor.stats().planar_regions, 1);
}

TEST(AffordanceExtractor, CurvedSurfaceDoesNotDriftFromItsSeedNormal) {
  // A strip of 15 facets, 1 mm long each, turning 2 degrees more at every facet (0 .. 28 deg).
  // Comparing with the seed normal gives regions of facets 0-4, 5-9 and 10-14; chaining
  // neighbour to neighbour would give one region.
  TriangleMesh strip;
  double x = 0.0, z = 0.0;
  for (int k = 0; k <= 15; ++k) {
    strip.vertices.emplace_back(x, 0.0, z);
    strip.vertices.emplace_back(x, 0.01, z);
    x += 0.001 * std::cos(2.0 * k * kDeg);
    z += 0.001 * std::sin(2.0 * k * kDeg);
  }
  for (int k = 0; k < 15; ++k) {
    strip.triangles.push_back({2 * k, 2 * k + 2, 2 * k + 3});
    strip.triangles.push_back({2 * k, 2 * k + 3, 2 * k + 1});
  }
  AffordanceExtractor extractor(Config(0.0, 0.0));
  const auto surfaces = extractor.Extract(strip);
  EXPECT_EQ(extractor.stats().planar_regions, 3);
  ASSERT_EQ(surfaces.size(), 3u);
  // Each region holds five facets at 0, 2, .. 8 degrees to its seed, seen from about 4 degrees.
  const double projected = 0.001 * 0.01 * (1.0 + 2.0 * std::cos(2 * kDeg) + 2.0 * std::cos(4 * kDeg));
  for (const auto& s : surfaces) EXPECT_NEAR(s.area, projected, 2e-9);
}

/// About 30 boxes: two floors, 16 blocks tilted 15 degrees in alternating directions, a plank,
/// side steps.
TriangleMesh Rubble() {
  TriangleMesh m = Box({2.0, 1.5, 0.2}, {-1.4, 0, -0.1});
  m.Append(Box({2.0, 1.5, 0.2}, {1.8, 0, -0.1}));
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const double tilt = 15 * kDeg * (((i + j) % 2) ? 1.0 : -1.0);
      const Eigen::Vector3d rpy = (i % 2) ? Eigen::Vector3d(tilt, 0, 0) : Eigen::Vector3d(0, tilt, 0);
      m.Append(Box({0.30, 0.21, 0.15}, {-0.4 + 0.31 * i, -0.45 + 0.3 * j, 0.12 + 0.02 * j}, rpy));
    }
  }
  m.Append(Box({0.30, 0.77, 0.34}, {0.22, 0, 0.17}));
  for (int k = 0; k < 4; ++k)
    m.Append(Box({0.3, 0.3, 0.1 + 0.1 * (k % 2)}, {0.6 + 0.3 * (k % 2), k < 2 ? -0.6 : 0.6, 0.05}));
  return m;
}

TEST(AffordanceExtractor, SameInputGivesIdenticalOutput) {
  const TriangleMesh rubble = Rubble();
  AffordanceExtractor a(Config(0.04));
  AffordanceExtractor b(Config(0.04));
  const auto first = a.Extract(rubble);
  a.Extract(Cells({{0, 0}, {1, 0}, {0, 1}}, 0.5, 0.0));  // the workspace holds other data now
  const auto again = a.Extract(rubble);
  const auto other = b.Extract(rubble);
  ASSERT_EQ(first.size(), 23u);
  for (const auto* run : {&again, &other}) {
    ASSERT_EQ(run->size(), first.size());
    for (std::size_t i = 0; i < first.size(); ++i) {
      EXPECT_EQ((*run)[i].vertices, first[i].vertices);
      EXPECT_EQ((*run)[i].normal, first[i].normal);
      EXPECT_EQ((*run)[i].area, first[i].area);
    }
  }
}

TEST(AffordanceExtractor, ReusedOutputVectorGivesTheSameSurfaces) {
  AffordanceExtractor extractor(Config(0.04));
  std::vector<AffordanceSurface> out(40);
  out[3].vertices.resize(17);
  extractor.Extract(Rubble(), out);
  const auto fresh = extractor.Extract(Rubble());
  ASSERT_EQ(out.size(), fresh.size());
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].vertices, fresh[i].vertices);
}

TEST(AffordanceExtractor, BadMeshesThrowInputError) {
  AffordanceExtractor extractor(Config(0.04));
  TriangleMesh nan = Box({1, 1, 1}, {0, 0, 0});
  nan.vertices[3].z() = std::numeric_limits<double>::quiet_NaN();
  try {
    extractor.Extract(nan);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "terrain mesh: vertex 3 is not finite");
  }
  TriangleMesh inf = Box({1, 1, 1}, {0, 0, 0});
  inf.vertices[0].x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(extractor.Extract(inf), InputError);
  TriangleMesh index = Box({1, 1, 1}, {0, 0, 0});
  index.triangles[5][1] = 8;
  EXPECT_THROW(extractor.Extract(index), InputError);
  index.triangles[5][1] = -1;
  EXPECT_THROW(extractor.Extract(index), InputError);
  EXPECT_THROW(extractor.Extract(TriangleMesh{}), InputError);
}

TEST(AffordanceExtractor, ExtremeCoordinatesNeitherHangNorCrash) {
  AffordanceExtractor extractor(Config(0.04));
  // Areas overflow double: every triangle is ignored.
  EXPECT_TRUE(extractor.Extract(Box({1e200, 1e200, 1e200}, {0, 0, 0})).empty());
  EXPECT_EQ(extractor.stats().degenerate_triangles, 12);
  // Far from the origin, welding cells are wider than one unit of the last place.
  const auto far = extractor.Extract(Box({1, 1, 1}, {1e13, 0, 0}));
  EXPECT_EQ(extractor.stats().planar_regions, 1);
  EXPECT_LE(far.size(), 1u);
}

TEST(AffordanceExtractor, DegenerateTrianglesAreIgnored) {
  TriangleMesh box = Box({1, 1, 1}, {0, 0, 0});
  const Eigen::Vector3d midpoint = 0.5 * (box.vertices[4] + box.vertices[5]);
  box.vertices.push_back(midpoint);
  box.triangles.push_back({4, 5, 8});  // zero area: three points on the top's front edge
  AffordanceExtractor extractor(Config(0.04));
  const auto surfaces = extractor.Extract(box);
  EXPECT_EQ(extractor.stats().degenerate_triangles, 1);
  ASSERT_EQ(surfaces.size(), 1u);
  EXPECT_NEAR(surfaces[0].area, 0.92 * 0.92, 1e-12);

  // A 1 m long sliver along the top's front edge, 0.5 um wide at one end: it has an area, but
  // two of its corners weld into one.
  TriangleMesh sliver = Box({1, 1, 1}, {0, 0, 0});
  sliver.vertices.push_back(sliver.vertices[5] + Eigen::Vector3d(0, 5e-7, 0));
  sliver.triangles.push_back({4, 5, 8});
  EXPECT_EQ(extractor.Extract(sliver).size(), 1u);
  EXPECT_EQ(extractor.stats().degenerate_triangles, 1);
  EXPECT_EQ(extractor.stats().candidate_triangles, 2);
}

}  // namespace
}  // namespace rbcp
