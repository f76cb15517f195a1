#include "convex_primitives.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace rbcp::limb_database_detail {
namespace {

using Kind = ConvexPrimitive::Kind;

ConvexPrimitive Sphere(const Eigen::Vector3d& c, double r) {
  ConvexPrimitive p;
  p.kind = Kind::kSphere;
  p.centre = c;
  p.radius = r;
  return p;
}

ConvexPrimitive Box(const Eigen::Vector3d& c, const Eigen::Vector3d& half,
                    const Eigen::Matrix3d& axes = Eigen::Matrix3d::Identity()) {
  ConvexPrimitive p;
  p.kind = Kind::kBox;
  p.centre = c;
  p.half = half;
  p.axes = axes;
  return p;
}

/// Capsule or cylinder along the z axis of `axes`, of total axis length `length`.
ConvexPrimitive Round(Kind kind, const Eigen::Vector3d& c, double radius, double length,
                      const Eigen::Matrix3d& axes = Eigen::Matrix3d::Identity()) {
  ConvexPrimitive p;
  p.kind = kind;
  p.centre = c;
  p.radius = radius;
  p.half = Eigen::Vector3d(0.0, 0.0, 0.5 * length);
  p.axes = axes;
  return p;
}

Eigen::Matrix3d RandomRotation(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

bool InsideBox(const Eigen::Vector3d& p, const ConvexPrimitive& b) {
  return ((b.axes.transpose() * (p - b.centre)).cwiseAbs() - b.half).maxCoeff() < 0.0;
}

TEST(ConvexPrimitives, SpheresOverlapOnlyWhenCloserThanTheRadiusSum) {
  EXPECT_TRUE(PrimitivesOverlap(Sphere({0, 0, 0}, 1.0), Sphere({1.9, 0, 0}, 1.0)));
  EXPECT_FALSE(PrimitivesOverlap(Sphere({0, 0, 0}, 1.0), Sphere({2.0, 0, 0}, 1.0)));  // touching
  EXPECT_FALSE(PrimitivesOverlap(Sphere({0, 0, 0}, 1.0), Sphere({2.1, 0, 0}, 1.0)));
}

TEST(ConvexPrimitives, SegmentDistances) {
  EXPECT_DOUBLE_EQ(PointSegmentDistance({0.5, 2.0, 0}, {0, 0, 0}, {1, 0, 0}), 2.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({3.0, 4.0, 0}, {0, 0, 0}, {0, 0, 0}), 5.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({-3.0, 4.0, 0}, {0, 0, 0}, {1, 0, 0}), 5.0);
  // Skew segments crossing at a distance 2 along z.
  EXPECT_NEAR(SegmentSegmentDistance({-1, 0, 0}, {1, 0, 0}, {0, -1, 2}, {0, 1, 2}), 2.0, 1e-15);
  // Parallel segments, offset and overlapping in x.
  EXPECT_NEAR(SegmentSegmentDistance({0, 0, 0}, {2, 0, 0}, {1, 3, 0}, {4, 3, 0}), 3.0, 1e-15);
  // Collinear, disjoint: gap between the ends.
  EXPECT_NEAR(SegmentSegmentDistance({0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {4, 0, 0}), 2.0, 1e-15);
}

TEST(ConvexPrimitives, PointAndSegmentToBoxDistances) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const ConvexPrimitive b = Box({1, 2, 3}, {0.5, 1.0, 1.5}, R);
  const Eigen::Vector3d c = b.centre;
  EXPECT_EQ(PointBoxDistance(c, b), 0.0);
  // Beyond a corner along the corner direction.
  const Eigen::Vector3d corner = c + R * Eigen::Vector3d(0.5, 1.0, 1.5);
  const Eigen::Vector3d outward = R * Eigen::Vector3d(1, 1, 1).normalized();
  EXPECT_NEAR(PointBoxDistance(corner + 0.3 * outward, b), 0.3, 1e-12);
  // A segment through the box, one parallel to a face, one whose closest point is interior.
  EXPECT_EQ(SegmentBoxDistance(c - R.col(0) * 5.0, c + R.col(0) * 5.0, b), 0.0);
  const Eigen::Vector3d above = c + R.col(2) * 2.5;  // 1.0 above the +z face
  EXPECT_NEAR(SegmentBoxDistance(above - R.col(0) * 3.0, above + R.col(1) * 0.2, b), 1.0, 1e-9);
  const Eigen::Vector3d a0 = c + R * Eigen::Vector3d(2.0, -3.0, 0.0);
  const Eigen::Vector3d a1 = c + R * Eigen::Vector3d(2.0, 3.0, 0.0);
  EXPECT_NEAR(SegmentBoxDistance(a0, a1, b), 1.5, 1e-9);
}

TEST(ConvexPrimitives, BoxSeparatingAxisTestAgreesWithSampledCommonPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int overlapping = 0;
  int separated = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const ConvexPrimitive a = Box({0, 0, 0}, {0.3 + 0.2 * u(rng), 0.3 + 0.2 * u(rng), 0.3 + 0.2 * u(rng)},
                                  RandomRotation(rng));
    const ConvexPrimitive b = Box({0.8 * u(rng), 0.8 * u(rng), 0.8 * u(rng)},
                                  {0.3 + 0.2 * u(rng), 0.1 + 0.05 * u(rng), 0.3 + 0.2 * u(rng)}, RandomRotation(rng));
    bool common = false;
    for (int s = 0; s < 4000 && !common; ++s) {
      const Eigen::Vector3d p = b.centre + b.axes * Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(b.half);
      common = InsideBox(p, a);
    }
    const bool sat = BoxesOverlap(a, b);
    EXPECT_EQ(sat, BoxesOverlap(b, a));
    if (common) {
      EXPECT_TRUE(sat) << "trial " << trial;
    }
    (sat ? overlapping : separated) += 1;
  }
  // Both outcomes must occur for the comparison to mean anything.
  EXPECT_GT(overlapping, 50);
  EXPECT_GT(separated, 50);
}

TEST(ConvexPrimitives, BoxesSeparatedOnlyByAnEdgeEdgeAxis) {
  // A unit cube and a second one turned so that one of its edges (along e1) faces the cube's
  // vertical edge at x = y = 0.5 across the diagonal d. No face normal separates them; only
  // z x e1 = d does.
  const ConvexPrimitive a = Box({0, 0, 0}, {0.5, 0.5, 0.5});
  const Eigen::Vector3d d = Eigen::Vector3d(1, 1, 0).normalized();
  const Eigen::Vector3d e1 = Eigen::Vector3d(1, -1, 0).normalized();
  const Eigen::Vector3d e2 = (std::sqrt(0.5) * d + std::sqrt(0.5) * Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Matrix3d axes;
  axes << e1, e2, e1.cross(e2);
  const double support = std::sqrt(0.5);  // of each cube along d
  for (double gap : {0.01, -0.01}) {
    const ConvexPrimitive b = Box((2.0 * support + gap) * d, {0.5, 0.5, 0.5}, axes);
    // The face axes alone would call them overlapping.
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d n = Eigen::Matrix3d::Identity().col(i);
      EXPECT_LT(std::abs(n.dot(b.centre)), 0.5 + (axes.transpose() * n).cwiseAbs().sum() * 0.5);
      const Eigen::Vector3d m = axes.col(i);
      EXPECT_LT(std::abs(m.dot(b.centre)), 0.5 * m.cwiseAbs().sum() + 0.5);
    }
    EXPECT_EQ(BoxesOverlap(a, b), gap < 0.0) << "gap " << gap;
    EXPECT_EQ(PrimitivesOverlap(b, a), gap < 0.0) << "gap " << gap;
  }
}

TEST(ConvexPrimitives, CapsulesAndSpheres) {
  const ConvexPrimitive cap = Round(Kind::kCapsule, {0, 0, 0}, 0.1, 1.0);
  EXPECT_TRUE(PrimitivesOverlap(cap, Sphere({0, 0, 0.62}, 0.05)));   // within the hemispherical cap
  EXPECT_FALSE(PrimitivesOverlap(cap, Sphere({0, 0, 0.66}, 0.05)));
  EXPECT_TRUE(PrimitivesOverlap(cap, Sphere({0.14, 0, 0.3}, 0.05)));
  EXPECT_FALSE(PrimitivesOverlap(cap, Sphere({0.16, 0, 0.3}, 0.05)));
  const ConvexPrimitive crossing = Round(Kind::kCapsule, {0.19, 0, 0}, 0.1, 1.0,
                                         Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix());
  EXPECT_TRUE(PrimitivesOverlap(cap, crossing));
  const ConvexPrimitive apart = Round(Kind::kCapsule, {0.21, 0, 0}, 0.1, 1.0,
                                      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix());
  EXPECT_FALSE(PrimitivesOverlap(cap, apart));
}

TEST(ConvexPrimitives, CylinderCapsAreFlat) {
  const ConvexPrimitive cyl = Round(Kind::kCylinder, {0, 0, 0}, 0.1, 1.0);
  // On the axis beyond the flat cap: a capsule would reach it, the cylinder does not.
  EXPECT_FALSE(PrimitivesOverlap(cyl, Sphere({0, 0, 0.58}, 0.05)));
  EXPECT_TRUE(PrimitivesOverlap(cyl, Sphere({0, 0, 0.54}, 0.05)));
  // Beside the mantle, level with the box corner: the box would reach it, the cylinder does not.
  const Eigen::Vector3d diagonal = Eigen::Vector3d(1, 1, 0).normalized();
  EXPECT_FALSE(PrimitivesOverlap(cyl, Sphere(0.13 * diagonal, 0.02)));
  EXPECT_TRUE(PrimitivesOverlap(cyl, Sphere(0.11 * diagonal, 0.02)));
  // A box 1 mm above the flat cap (inside the capsule's cap), then pushed into the cylinder.
  EXPECT_FALSE(PrimitivesOverlap(cyl, Box({0, 0, 0.601}, {0.2, 0.2, 0.1})));
  EXPECT_TRUE(PrimitivesOverlap(cyl, Box({0, 0, 0.59}, {0.2, 0.2, 0.1})));
}

}  // namespace
}  // namespace rbcp::limb_database_detail
