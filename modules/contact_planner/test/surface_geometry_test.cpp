#include "surface_geometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rbcp::contact_planner_detail {
namespace {

ConvexPolygon3d Square(double half, double z) {
  return ConvexPolygon3d({{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}}, Eigen::Vector3d::UnitZ());
}

TEST(SurfaceGeometryTest, ClosestPointIsInsideOrOnTheBoundary) {
  const ConvexPolygon3d s = Square(1.0, 0.2);
  EXPECT_LT((s.ClosestPoint({0.3, -0.4, 1.0}) - Eigen::Vector3d(0.3, -0.4, 0.2)).norm(), 1e-12);
  EXPECT_LT((s.ClosestPoint({2.0, 0.5, 0.0}) - Eigen::Vector3d(1.0, 0.5, 0.2)).norm(), 1e-12);
  EXPECT_LT((s.ClosestPoint({3.0, 3.0, 0.2}) - Eigen::Vector3d(1.0, 1.0, 0.2)).norm(), 1e-12);
  EXPECT_TRUE(s.Contains({0.99, 0.0, 0.2005}, 1e-3, 0.0));
  EXPECT_FALSE(s.Contains({1.01, 0.0, 0.2}, 1e-3, 0.0));
  EXPECT_FALSE(s.Contains({0.0, 0.0, 0.21}, 1e-3, 0.0));
}

TEST(SurfaceGeometryTest, ClockwiseInputIsReordered) {
  const ConvexPolygon3d s({{-1, -1, 0}, {-1, 1, 0}, {1, 1, 0}, {1, -1, 0}}, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(s.Contains({0.5, 0.5, 0.0}, 1e-9, 0.0));
  EXPECT_LT((s.ClosestPoint({0.5, 0.5, 1.0}) - Eigen::Vector3d(0.5, 0.5, 0.0)).norm(), 1e-12);
}

TEST(SurfaceGeometryTest, PointAtFollowsAnInclinedPlane) {
  const double a = 0.26;
  const Eigen::Vector3d n(-std::sin(a), 0.0, std::cos(a));
  const Eigen::Vector3d t(std::cos(a), 0.0, std::sin(a));
  const ConvexPolygon3d s({-t - Eigen::Vector3d::UnitY(), t - Eigen::Vector3d::UnitY(), t + Eigen::Vector3d::UnitY(),
                           -t + Eigen::Vector3d::UnitY()},
                          n);
  const auto p = s.PointAt({0.5, 0.2});
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->z(), 0.5 * std::tan(a), 1e-12);
  EXPECT_NEAR(s.PlaneDistance(*p), 0.0, 1e-12);
}

TEST(SurfaceGeometryTest, ClipToSquareKeepsTheOverlap) {
  const ConvexPolygon3d s = Square(1.0, 0.0);
  const auto clipped = s.ClipToSquare({0.9, 0.0}, 0.3);
  ASSERT_GE(clipped.size(), 4u);
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (const auto& v : clipped) {
    min_x = std::min(min_x, v.x());
    max_x = std::max(max_x, v.x());
    min_y = std::min(min_y, v.y());
    max_y = std::max(max_y, v.y());
  }
  EXPECT_NEAR(min_x, 0.6, 1e-12);
  EXPECT_NEAR(max_x, 1.0, 1e-12);
  EXPECT_NEAR(min_y, -0.3, 1e-12);
  EXPECT_NEAR(max_y, 0.3, 1e-12);
  EXPECT_TRUE(s.ClipToSquare({3.0, 0.0}, 0.3).empty());
}

TEST(SurfaceGeometryTest, ClipToRectangleFollowsItsAxes) {
  const ConvexPolygon3d s = Square(1.0, 0.0);
  // A 0.4 x 0.2 rectangle turned by 45 degrees, centred inside the square: kept whole.
  const Eigen::Vector2d axis(std::sqrt(0.5), std::sqrt(0.5));
  const auto inside = s.ClipToRectangle({0.0, 0.0}, axis, 0.2, 0.1);
  ASSERT_EQ(inside.size(), 4u);
  double area = 0.0;
  for (std::size_t i = 0; i < inside.size(); ++i) {
    const Eigen::Vector3d& a = inside[i];
    const Eigen::Vector3d& b = inside[(i + 1) % inside.size()];
    area += 0.5 * (a.x() * b.y() - b.x() * a.y());
  }
  EXPECT_NEAR(std::abs(area), 0.4 * 0.2, 1e-12);
  for (const auto& v : inside) {
    EXPECT_LE(std::abs(axis.dot(v.head<2>())), 0.2 + 1e-12);
    EXPECT_LE(std::abs(Eigen::Vector2d(-axis.y(), axis.x()).dot(v.head<2>())), 0.1 + 1e-12);
  }
  // Over the corner (1, 1): only the part inside the square is left.
  const auto corner = s.ClipToRectangle({1.0, 1.0}, axis, 0.2, 0.1);
  ASSERT_GE(corner.size(), 3u);
  for (const auto& v : corner) {
    EXPECT_LE(v.x(), 1.0 + 1e-12);
    EXPECT_LE(v.y(), 1.0 + 1e-12);
  }
  EXPECT_TRUE(s.ClipToRectangle({3.0, 0.0}, axis, 0.2, 0.1).empty());
}

}  // namespace
}  // namespace rbcp::contact_planner_detail
