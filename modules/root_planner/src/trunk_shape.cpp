#include "rbcp/root_planner/trunk_shape.h"

#include <vector>

namespace rbcp {

ConvexPolytope MakeTrunkShape(const TrunkShapeConfig& config) {
  const Eigen::Vector3d& lo = config.box_min;
  const Eigen::Vector3d& hi = config.box_max;
  std::vector<Eigen::Vector3d> points;
  for (double x : {lo.x(), hi.x()}) {
    for (double y : {lo.y(), hi.y()}) {
      for (double z : {lo.z(), hi.z()}) points.emplace_back(x, y, z);
    }
  }
  if (config.keel_bottom_z < lo.z()) {
    const double xc = 0.5 * (lo.x() + hi.x());
    for (double x : {xc - config.keel_half_length, xc + config.keel_half_length}) {
      for (double y : {lo.y(), hi.y()}) points.emplace_back(x, y, config.keel_bottom_z);
    }
  }
  return ConvexHull(points);
}

}  // namespace rbcp
