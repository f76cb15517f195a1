#include "rbcp/equilibrium/support_polygon.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

// Feet in leg order LF, RF, LH, RH (not a cyclic order), at different heights.
std::vector<Eigen::Vector3d> Rectangle() {
  return {{0.3, 0.2, 0.1}, {0.3, -0.2, 0.0}, {-0.3, 0.2, -0.05}, {-0.3, -0.2, 0.2}};
}

TEST(SupportPolygon, RectangleMarginsByHand) {
  const auto feet = Rectangle();
  EXPECT_NEAR(SupportPolygonMargin(feet, {0.0, 0.0, 0.5}), 0.2, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {0.25, 0.0, 0.5}), 0.05, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {0.1, -0.15, 0.5}), 0.05, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {0.3, 0.0, 0.5}), 0.0, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {0.4, 0.0, 0.5}), -0.1, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {0.4, 0.3, 0.5}), -std::sqrt(0.02), 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {-0.5, -0.2, 0.0}), -0.2, 1e-12);
}

TEST(SupportPolygon, CentreOfPressureByHand) {
  const auto feet = Rectangle();
  // Equal forces: the centre of the rectangle, 0.2 m inside it.
  CentreOfPressure cop = ComputeCentreOfPressure(feet, {100, 100, 100, 100});
  EXPECT_NEAR(cop.position.x(), 0.0, 1e-12);
  EXPECT_NEAR(cop.position.y(), 0.0, 1e-12);
  EXPECT_NEAR(cop.margin_m, 0.2, 1e-12);
  // Three times the force on the fore feet: x = 0.3 * (300 - 100) / 400 = 0.15; a pulling foot
  // counts as none.
  cop = ComputeCentreOfPressure(feet, {150, 150, 50, 50});
  EXPECT_NEAR(cop.position.x(), 0.15, 1e-12);
  EXPECT_NEAR(cop.margin_m, 0.15, 1e-12);
  cop = ComputeCentreOfPressure(feet, {100, 100, 100, -50});
  EXPECT_NEAR(cop.position.x(), 0.1, 1e-12);
  EXPECT_NEAR(cop.position.y(), 200.0 * 0.2 / 300.0 - 100.0 * 0.2 / 300.0, 1e-12);
  // Two feet, or hardly any force: none.
  EXPECT_TRUE(std::isnan(ComputeCentreOfPressure({feet[0], feet[1]}, {100, 100}).margin_m));
  EXPECT_TRUE(std::isnan(ComputeCentreOfPressure(feet, {0.2, 0.2, 0.2, 0.2}).margin_m));
  EXPECT_THROW(ComputeCentreOfPressure(feet, {1.0}), InputError);
}

TEST(SupportPolygon, TriangleMarginsByHand) {
  const std::vector<Eigen::Vector3d> feet = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_NEAR(SupportPolygonMargin(feet, {0.25, 0.25, 1}), 0.25, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {0.4, 0.4, 1}), 0.2 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {1, 1, 1}), -1.0 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(feet, {-0.3, -0.4, 1}), -0.5, 1e-12);
  // Same triangle given clockwise.
  const std::vector<Eigen::Vector3d> cw = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}};
  EXPECT_NEAR(SupportPolygonMargin(cw, {0.25, 0.25, 1}), 0.25, 1e-12);
}

TEST(SupportPolygon, ThreeStanceFeetOfFour) {
  // LH swings: the support triangle is LF, RF, RH; its diagonal runs from RH to LF.
  const auto all = Rectangle();
  const std::vector<Eigen::Vector3d> stance = {all[0], all[1], all[3]};
  // Distance from (x, y) to the diagonal through RH (-0.3, -0.2) and LF (0.3, 0.2).
  auto to_diagonal = [](double x, double y) { return std::abs(0.4 * x - 0.6 * y) / std::hypot(0.6, 0.4); };
  EXPECT_NEAR(SupportPolygonMargin(stance, {0.1, -0.05, 0.4}), std::min({to_diagonal(0.1, -0.05), 0.15, 0.2}), 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(stance, {0.0, 0.0, 0.4}), 0.0, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(stance, {-0.1, 0.05, 0.4}), -to_diagonal(-0.1, 0.05), 1e-12);
}

TEST(SupportPolygon, DegenerateStances) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {0.5, 0, 0.2}};
  EXPECT_NEAR(SupportPolygonMargin(line, {0.5, 0.0, 1}), 0.0, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(line, {0.5, 0.3, 1}), -0.3, 1e-12);
  EXPECT_NEAR(SupportPolygonMargin(line, {1.3, -0.4, 1}), -0.5, 1e-12);
  const std::vector<Eigen::Vector3d> point = {{1, 1, 0}, {1, 1, 0.3}};
  EXPECT_NEAR(SupportPolygonMargin(point, {1.3, 1.4, 0}), -0.5, 1e-12);
  EXPECT_THROW(SupportPolygonMargin(std::vector<Eigen::Vector3d>{}, {0, 0, 0}), InputError);
}

TEST(SupportPolygon, HullDropsInteriorAndCollinearPoints) {
  const auto hull = ConvexHull2d({{0, 0}, {2, 0}, {1, 0}, {2, 2}, {0, 2}, {1, 1}, {0, 1}, {2, 2}});
  ASSERT_EQ(hull.size(), 4u);
  double area2 = 0.0;  // positive for counter-clockwise
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const auto& a = hull[i];
    const auto& b = hull[(i + 1) % hull.size()];
    area2 += a.x() * b.y() - a.y() * b.x();
  }
  EXPECT_NEAR(area2, 8.0, 1e-12);
}

TEST(SupportPolygon, ContactOverloadUsesPositions) {
  std::vector<ContactPoint> contacts;
  for (const auto& p : Rectangle()) contacts.push_back({p, Eigen::Vector3d::UnitZ()});
  EXPECT_NEAR(SupportPolygonMargin(contacts, {0.25, 0.0, 0.5}), 0.05, 1e-12);
}

TEST(SupportTriangle, ErodedTriangleKeepsTheMargin) {
  const std::array<Eigen::Vector2d, 3> tri = {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)};
  const auto e = ErodeTriangle(tri, 0.1);
  ASSERT_TRUE(e.has_value());
  // Each eroded vertex is 0.1 from the two edges it faces.
  for (const auto& v : *e) {
    const double d_x = v.y();
    const double d_y = v.x();
    const double d_h = (1.0 - v.x() - v.y()) / std::sqrt(2.0);
    EXPECT_GE(std::min({d_x, d_y, d_h}), 0.1 - 1e-12);
    EXPECT_NEAR(std::min({d_x, d_y, d_h}), 0.1, 1e-12);
  }
  EXPECT_FALSE(ErodeTriangle(tri, 0.3).has_value());  // inradius 0.293
}

TEST(SupportTriangle, ClosestPointInTriangle) {
  const std::array<Eigen::Vector2d, 3> tri = {Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 0)};
  EXPECT_LT((ClosestPointInTriangle(tri, {0.2, 0.2}) - Eigen::Vector2d(0.2, 0.2)).norm(), 1e-12);
  EXPECT_LT((ClosestPointInTriangle(tri, {1.0, 1.0}) - Eigen::Vector2d(0.5, 0.5)).norm(), 1e-12);
  EXPECT_LT((ClosestPointInTriangle(tri, {-1.0, -1.0}) - Eigen::Vector2d(0.0, 0.0)).norm(), 1e-12);
}

}  // namespace
}  // namespace rbcp
