#include "rbcp/root_planner/trunk_shape.h"

#include <vector>

#include "rbcp/core/config_checks.h"

namespace rbcp {

TrunkShapeConfig TrunkShapeConfig::Load(const YamlMap& map) {
  TrunkShapeConfig c;
  c.box_min = map.Vector3("box_min");
  c.box_max = map.Vector3("box_max");
  c.keel_bottom_z = map.Double("keel_bottom_z");
  c.keel_half_length = map.Double("keel_half_length");
  map.RejectUnknownKeys();
  const std::string problem = c.Problem();
  if (!problem.empty()) map.Fail("", problem);
  return c;
}

std::string TrunkShapeConfig::Problem() const {
  for (int i = 0; i < 3; ++i) {
    if (!(box_max[i] > box_min[i])) {
      return "'box_max': expected every coordinate above box_min's, got " + ConfigNumber(box_max[i]) + " <= " +
             ConfigNumber(box_min[i]);
    }
  }
  if (!(keel_bottom_z <= box_min.z())) {
    return "'keel_bottom_z': expected at most box_min z (" + ConfigNumber(box_min.z()) + "), got " +
           ConfigNumber(keel_bottom_z);
  }
  if (!(keel_half_length > 0.0 && keel_half_length < 0.5 * (box_max.x() - box_min.x()))) {
    return "'keel_half_length': expected a length in (0, half the box length), got " + ConfigNumber(keel_half_length);
  }
  return "";
}

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
