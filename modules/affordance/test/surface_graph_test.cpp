#include "rbcp/affordance/surface_graph.h"

#include <gtest/gtest.h>

namespace rbcp {
namespace {

/// A horizontal rectangle [x0, x1] x [y0, y1] at height z.
AffordanceSurface Rect(double x0, double x1, double y0, double y1, double z) {
  AffordanceSurface s;
  s.vertices = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  s.area = (x1 - x0) * (y1 - y0);
  return s;
}

TEST(SurfaceGraphTest, DistancesBetweenPointsAndPolygons) {
  const AffordanceSurface a = Rect(0, 1, 0, 1, 0);
  EXPECT_NEAR(PointPolygonDistance({0.5, 0.5, 0.3}, a), 0.3, 1e-12);  // over the face
  EXPECT_NEAR(PointPolygonDistance({1.4, 0.5, 0.0}, a), 0.4, 1e-12);  // beside an edge
  EXPECT_NEAR(PointPolygonDistance({1.3, 1.4, 0.0}, a), 0.5, 1e-12);  // beside a corner
  EXPECT_NEAR(PolygonDistance(a, Rect(1.2, 2, 0, 1, 0)), 0.2, 1e-12);  // a gap
  EXPECT_NEAR(PolygonDistance(a, Rect(1.2, 2, 0, 1, 0.15)), std::hypot(0.2, 0.15), 1e-12);  // a step up
  EXPECT_NEAR(PolygonDistance(a, Rect(0.2, 0.4, 0.2, 0.4, 0.3)), 0.3, 1e-12);  // a block over it
  EXPECT_NEAR(PolygonDistance(a, Rect(0.5, 2, 0.5, 2, 0)), 0.0, 1e-12);  // overlapping
}

TEST(SurfaceGraphTest, SurfacesWithinTheGapAreOneComponent) {
  // Stepping stones 0.3 m apart, then a 1 m gap to a far platform.
  const std::vector<AffordanceSurface> surfaces = {Rect(0, 1, 0, 1, 0), Rect(1.3, 1.6, 0, 1, 0.1),
                                                   Rect(1.9, 2.2, 0, 1, 0), Rect(3.2, 4, 0, 1, 0)};
  const SurfaceGraph graph(surfaces, 0.4);
  EXPECT_EQ(graph.ComponentCount(), 2);
  EXPECT_EQ(graph.Components()[0], graph.Components()[2]);
  EXPECT_NE(graph.Components()[0], graph.Components()[3]);
  const std::vector<int> start = graph.SurfacesNear({0.5, 0.5, 0.45}, 0.6);
  EXPECT_EQ(start, std::vector<int>{0});
  EXPECT_TRUE(graph.Joined(start, graph.SurfacesNear({2.0, 0.5, 0.45}, 0.6)));
  EXPECT_FALSE(graph.Joined(start, graph.SurfacesNear({3.6, 0.5, 0.45}, 0.6)));
  EXPECT_FALSE(graph.Joined(start, {}));
  // A longer reach bridges the gap.
  EXPECT_EQ(SurfaceGraph(surfaces, 1.1).ComponentCount(), 1);
}

TEST(SurfaceGraphTest, NoSurfacesNoComponents) {
  const SurfaceGraph graph({}, 0.5);
  EXPECT_EQ(graph.ComponentCount(), 0);
  EXPECT_TRUE(graph.SurfacesNear(Eigen::Vector3d::Zero(), 10.0).empty());
}

}  // namespace
}  // namespace rbcp
