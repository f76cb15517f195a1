#include "rbcp/root_planner/convex_polytope.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>

#include "rbcp/core/error.h"
#include "rbcp/root_planner/trunk_shape.h"

namespace rbcp {
namespace {

std::vector<Eigen::Vector3d> CubeCorners(double side, const Eigen::Vector3d& center) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 8; ++i) {
    points.push_back(center + 0.5 * side * Eigen::Vector3d((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1));
  }
  return points;
}

void ExpectOutwardAndConvex(const ConvexPolytope& poly) {
  const Eigen::Vector3d c = poly.Centroid();
  EXPECT_LT(poly.PlaneDistance(c), 0.0);
  for (const auto& t : poly.triangles) {
    const Eigen::Vector3d& a = poly.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d n =
        (poly.vertices[static_cast<std::size_t>(t[1])] - a).cross(poly.vertices[static_cast<std::size_t>(t[2])] - a);
    EXPECT_GT(n.dot(a - c), 0.0);
    for (const auto& v : poly.vertices) EXPECT_LE(n.normalized().dot(v - a), 1e-9);
  }
}

TEST(ConvexHullTest, CubeWithInteriorPoints) {
  auto points = CubeCorners(2.0, {1.0, -1.0, 0.5});
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  for (int i = 0; i < 100; ++i) points.push_back(Eigen::Vector3d(1.0, -1.0, 0.5) + Eigen::Vector3d(u(rng), u(rng), u(rng)));
  const ConvexPolytope hull = ConvexHull(points);
  EXPECT_EQ(hull.vertices.size(), 8u);
  EXPECT_EQ(hull.triangles.size(), 12u);
  EXPECT_NEAR(hull.Volume(), 8.0, 1e-12);
  EXPECT_TRUE(hull.Centroid().isApprox(Eigen::Vector3d(1.0, -1.0, 0.5), 1e-12));
  ExpectOutwardAndConvex(hull);
  const auto [lo, hi] = hull.Bounds();
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3d(0.0, -2.0, -0.5)));
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3d(2.0, 0.0, 1.5)));
  const ConvexPolytope half = hull.Scaled(0.5, hull.Centroid());
  EXPECT_NEAR(half.Volume(), 1.0, 1e-12);
}

TEST(ConvexHullTest, RejectsFlatOrTooFewPoints) {
  EXPECT_THROW(ConvexHull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), InputError);
  EXPECT_THROW(ConvexHull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 0}}), InputError);
}

TEST(SimplifiedConvexHullTest, BoundedTrianglesInsideTheFullHull) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d d(n(rng), n(rng), n(rng));
    points.push_back(d.normalized().cwiseProduct(Eigen::Vector3d(0.5, 0.3, 0.4)));
  }
  const ConvexPolytope full = ConvexHull(points);
  ASSERT_GT(full.triangles.size(), 1000u);
  const ConvexPolytope simple = SimplifiedConvexHull(points, 200, 0.0);
  EXPECT_LE(simple.triangles.size(), 200u);
  EXPECT_GE(simple.triangles.size(), 150u);
  ExpectOutwardAndConvex(simple);
  // An inner approximation made of input points, close in volume.
  for (const auto& v : simple.vertices) EXPECT_LE(full.PlaneDistance(v), 1e-9);
  EXPECT_LE(simple.Volume(), full.Volume());
  EXPECT_GT(simple.Volume(), 0.9 * full.Volume());
  // A loose tolerance stops earlier.
  const ConvexPolytope coarse = SimplifiedConvexHull(points, 200, 0.05);
  EXPECT_LT(coarse.triangles.size(), simple.triangles.size());
  for (const auto& p : points) EXPECT_LE(coarse.PlaneDistance(p), 0.05 + 1e-9);
  // Deterministic.
  const ConvexPolytope again = SimplifiedConvexHull(points, 200, 0.0);
  ASSERT_EQ(again.vertices.size(), simple.vertices.size());
  for (std::size_t i = 0; i < again.vertices.size(); ++i) EXPECT_EQ(again.vertices[i], simple.vertices[i]);
}

TEST(ObjTest, RoundTripAndValidation) {
  const ConvexPolytope hull = ConvexHull(CubeCorners(0.3, {0.1, 0.2, -0.3}));
  const std::string path = ::testing::TempDir() + "/rbcp_cube.obj";
  SaveObj(hull, path, {"a cube", "second line"});
  const ConvexPolytope loaded = LoadConvexObj(path);
  ASSERT_EQ(loaded.vertices.size(), hull.vertices.size());
  ASSERT_EQ(loaded.triangles, hull.triangles);
  for (std::size_t i = 0; i < hull.vertices.size(); ++i) EXPECT_EQ(loaded.vertices[i], hull.vertices[i]);

  // A face turned inside out is not a convex polytope with outward faces.
  ConvexPolytope flipped = hull;
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  SaveObj(flipped, path);
  EXPECT_THROW(LoadConvexObj(path), InputError);
  {
    std::ofstream bad(path);
    bad << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
  }
  EXPECT_THROW(LoadConvexObj(path), InputError);
  {
    std::ofstream bad(path);
    bad << "v 0 0 zero\n";
  }
  EXPECT_THROW(LoadConvexObj(path), InputError);
  std::remove(path.c_str());
  EXPECT_THROW(LoadConvexObj(path), InputError);
}

// Reference overlap test: the triangle clipped by every face plane of the polytope (Sutherland-
// Hodgman) is non-empty exactly when the two share a point.
bool ClippedTriangleRemains(const ConvexPolytope& poly, const std::array<Eigen::Vector3d, 3>& tri) {
  std::vector<Eigen::Vector3d> polygon(tri.begin(), tri.end());
  for (const auto& t : poly.triangles) {
    const Eigen::Vector3d& a = poly.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d n =
        (poly.vertices[static_cast<std::size_t>(t[1])] - a).cross(poly.vertices[static_cast<std::size_t>(t[2])] - a).normalized();
    std::vector<Eigen::Vector3d> kept;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector3d& p = polygon[i];
      const Eigen::Vector3d& q = polygon[(i + 1) % polygon.size()];
      const double dp = n.dot(p - a), dq = n.dot(q - a);
      if (dp <= 0.0) kept.push_back(p);
      if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) kept.push_back(p + dp / (dp - dq) * (q - p));
    }
    polygon = std::move(kept);
    if (polygon.empty()) return false;
  }
  return true;
}

TEST(PolytopeTriangleTest, AgreesWithClippingTheTriangleOnRandomTriangles) {
  TrunkShapeConfig config;
  const std::vector<ConvexPolytope> shapes = {MakeTrunkShape(config), ConvexHull(CubeCorners(0.4, {0.1, -0.2, 0.3}))};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-0.6, 0.6);
  std::normal_distribution<double> offset(0.0, 0.15);
  for (const ConvexPolytope& shape : shapes) {
    const PolytopeTriangleTest test(shape);
    int overlapping = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      // Triangles of every size near the shape: small ones about a random point, large slabs.
      const Eigen::Vector3d c(coordinate(rng), coordinate(rng), coordinate(rng));
      const double scale = (i % 3 == 0) ? 5.0 : 1.0;
      std::array<Eigen::Vector3d, 3> tri;
      for (auto& v : tri) v = c + scale * Eigen::Vector3d(offset(rng), offset(rng), offset(rng));
      const bool expected = ClippedTriangleRemains(shape, tri);
      overlapping += expected ? 1 : 0;
      ASSERT_EQ(test.Overlaps(tri[0], tri[1], tri[2]), expected) << "triangle " << i;
    }
    // Both answers are well represented.
    EXPECT_GT(overlapping, n / 10);
    EXPECT_LT(overlapping, n - n / 10);
  }
}

TEST(PolytopeTriangleTest, ATriangleThroughTheMiddleWithNoCornerInsideOverlaps) {
  const ConvexPolytope cube = ConvexHull(CubeCorners(1.0, Eigen::Vector3d::Zero()));
  const PolytopeTriangleTest test(cube);
  // A large horizontal triangle slicing the cube: no vertex of either inside the other.
  EXPECT_TRUE(test.Overlaps({-5.0, -5.0, 0.1}, {5.0, -5.0, 0.1}, {0.0, 5.0, 0.1}));
  EXPECT_FALSE(test.Overlaps({-5.0, -5.0, 0.6}, {5.0, -5.0, 0.6}, {0.0, 5.0, 0.6}));
  // An edge-on triangle passing a cube edge diagonally, just clear of it.
  EXPECT_FALSE(test.Overlaps({0.6, 0.5, -1.0}, {0.5, 0.6, -1.0}, {0.55, 0.55, 1.0}));
  EXPECT_TRUE(test.Overlaps({0.45, 0.5, -1.0}, {0.5, 0.45, -1.0}, {0.47, 0.47, 1.0}));
  // Degenerate triangles: a segment through the cube, a point inside, a point outside.
  EXPECT_TRUE(test.Overlaps({-2.0, 0.0, 0.0}, {2.0, 0.0, 0.0}, {2.0, 0.0, 0.0}));
  EXPECT_TRUE(test.Overlaps({0.1, 0.1, 0.1}, {0.1, 0.1, 0.1}, {0.1, 0.1, 0.1}));
  EXPECT_FALSE(test.Overlaps({0.1, 0.1, 0.6}, {0.1, 0.1, 0.6}, {0.1, 0.1, 0.6}));
}

TEST(TrunkShapeTest, BoxWithKeel) {
  TrunkShapeConfig config;  // the bare trunk's width
  config.box_min = {-0.30, -0.165, -0.15};
  config.box_max = {0.30, 0.165, 0.24};
  const ConvexPolytope trunk = MakeTrunkShape(config);
  EXPECT_EQ(trunk.vertices.size(), 12u);
  const auto [lo, hi] = trunk.Bounds();
  EXPECT_NEAR(lo.z(), -0.325, 1e-12);
  EXPECT_NEAR(hi.z(), 0.24, 1e-12);
  EXPECT_NEAR(lo.x(), -0.30, 1e-12);
  EXPECT_NEAR(hi.y(), 0.165, 1e-12);
  // Box volume plus the trapezoidal keel prism: (0.6 + 0.1) / 2 * 0.175 * 0.33.
  EXPECT_NEAR(trunk.Volume(), 0.6 * 0.33 * 0.39 + 0.5 * (0.6 + 0.1) * 0.175 * 0.33, 1e-12);
  // The keel bottom is flat over x in [-0.05, 0.05]; under the front the box bottom is at -0.15.
  EXPECT_LE(trunk.PlaneDistance({0.0, 0.0, -0.32}), 0.0);
  EXPECT_GT(trunk.PlaneDistance({0.28, 0.0, -0.2}), 0.0);
  EXPECT_LE(trunk.PlaneDistance({0.28, 0.0, -0.14}), 0.0);
  ExpectOutwardAndConvex(trunk);

  TrunkShapeConfig bad = config;
  bad.keel_bottom_z = -0.1;
  EXPECT_THROW(bad.Validate(), InputError);
  bad = config;
  bad.box_max.y() = -0.2;
  EXPECT_THROW(bad.Validate(), InputError);
}

}  // namespace
}  // namespace rbcp
