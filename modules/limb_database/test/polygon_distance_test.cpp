#include "polygon_distance.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "rbcp/core/error.h"

namespace rbcp::limb_database_detail {
namespace {

std::vector<Eigen::Vector3d> UnitSquare() { return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}; }

TEST(ConvexPolygonDistance, InsideOutsideAndClosestPoint) {
  const ConvexPolygonDistance square(UnitSquare(), Eigen::Vector3d(0, 0, 2));
  Eigen::Vector3d c;
  EXPECT_DOUBLE_EQ(square.Distance({0.3, 0.6, 0.25}, &c), 0.25);
  EXPECT_TRUE(c.isApprox(Eigen::Vector3d(0.3, 0.6, 0.0)));
  EXPECT_DOUBLE_EQ(square.Distance({0.3, 0.6, -0.5}), 0.5);
  EXPECT_DOUBLE_EQ(square.Distance({0.5, 0.5, 0.0}), 0.0);
  // Beside an edge and beyond a corner.
  EXPECT_NEAR(square.Distance({1.3, 0.5, 0.4}, &c), 0.5, 1e-15);
  EXPECT_TRUE(c.isApprox(Eigen::Vector3d(1.0, 0.5, 0.0)));
  EXPECT_NEAR(square.Distance({-0.3, -0.4, 0.0}, &c), 0.5, 1e-15);
  EXPECT_TRUE(c.isApprox(Eigen::Vector3d(0.0, 0.0, 0.0)));
  EXPECT_EQ(square.Min(), Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(square.Max(), Eigen::Vector3d(1, 1, 0));
}

TEST(ConvexPolygonDistance, WindingAndNormalSignDoNotMatter) {
  std::vector<Eigen::Vector3d> cw = UnitSquare();
  std::reverse(cw.begin(), cw.end());
  const ConvexPolygonDistance a(UnitSquare(), Eigen::Vector3d::UnitZ());
  const ConvexPolygonDistance b(cw, Eigen::Vector3d::UnitZ());
  const ConvexPolygonDistance c(UnitSquare(), -Eigen::Vector3d::UnitZ());
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.5, 0.5, 0.2), Eigen::Vector3d(1.5, -0.5, 0.3),
                                   Eigen::Vector3d(0.9, 0.1, -0.7), Eigen::Vector3d(-2.0, 0.5, 0.0)}) {
    EXPECT_DOUBLE_EQ(a.Distance(p), b.Distance(p));
    EXPECT_DOUBLE_EQ(a.Distance(p), c.Distance(p));
  }
}

TEST(ConvexPolygonDistance, TiltedTriangleMatchesTheFrameChange) {
  const Eigen::Isometry3d T = Eigen::Translation3d(0.2, -1.0, 0.5) *
                              Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, -2, 0.5).normalized());
  std::vector<Eigen::Vector3d> tri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<Eigen::Vector3d> tri_moved;
  for (const auto& v : tri) tri_moved.push_back(T * v);
  const ConvexPolygonDistance flat(tri, Eigen::Vector3d::UnitZ());
  const ConvexPolygonDistance moved(tri_moved, T.linear() * Eigen::Vector3d::UnitZ());
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.2, 0.2, 0.3), Eigen::Vector3d(0.8, 0.8, -0.1),
                                   Eigen::Vector3d(-0.5, 2.0, 0.4), Eigen::Vector3d(2.0, -1.0, 0.0)}) {
    EXPECT_NEAR(flat.Distance(p), moved.Distance(T * p), 1e-12);
  }
  EXPECT_NEAR(flat.Distance({0.8, 0.8, 0.0}), std::sqrt(2.0) * 0.3, 1e-15);
}

TEST(ConvexPolygonDistance, RejectsDegenerateInput) {
  EXPECT_THROW(ConvexPolygonDistance({{0, 0, 0}, {1, 0, 0}}, Eigen::Vector3d::UnitZ()), InputError);
  EXPECT_THROW(ConvexPolygonDistance(UnitSquare(), Eigen::Vector3d::Zero()), InputError);
  EXPECT_TRUE(ConvexPolygonDistance({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, Eigen::Vector3d::UnitZ()).Degenerate());
  EXPECT_TRUE(ConvexPolygonDistance({{0, 0, 0}, {1, 0, 0}, {1, 0, 0}}, Eigen::Vector3d::UnitZ()).Degenerate());
  // A square seen edge-on from its normal has no area about it.
  EXPECT_TRUE(ConvexPolygonDistance(UnitSquare(), Eigen::Vector3d::UnitX()).Degenerate());
  EXPECT_FALSE(ConvexPolygonDistance(UnitSquare(), Eigen::Vector3d::UnitZ()).Degenerate());
  EXPECT_THROW(ConvexPolygonDistance({{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}}, Eigen::Vector3d::UnitZ()), InputError);
}

}  // namespace
}  // namespace rbcp::limb_database_detail
