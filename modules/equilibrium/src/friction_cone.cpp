#include "rbcp/equilibrium/friction_cone.h"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

// Below this tilt [rad] a surface counts as horizontal and has no up-slope direction.
constexpr double kHorizontalTilt = 1e-3;

}  // namespace

void ContactTangents(const Eigen::Vector3d& n, Eigen::Vector3d* t1, Eigen::Vector3d* t2) {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ() - n.z() * n;  // world z projected onto the plane
  if (up.norm() < std::sin(kHorizontalTilt)) {
    up = Eigen::Vector3d::UnitX() - n.x() * n;
    if (up.norm() < 1e-6) up = Eigen::Vector3d::UnitY() - n.y() * n;  // n is +-x
  }
  *t1 = up.normalized();
  *t2 = n.cross(*t1);
}

Eigen::Matrix3Xd FrictionConeGenerators(const Eigen::Vector3d& normal, double mu, int count) {
  const double len = normal.norm();
  if (!normal.allFinite() || !(len > 1e-9)) {
    std::ostringstream os;
    os << "friction cone: expected a finite non-zero normal, got (" << normal.transpose() << ")";
    throw InputError(os.str());
  }
  if (!(std::isfinite(mu) && mu > 0.0)) {
    throw InputError("friction cone: expected a positive friction coefficient, got " + std::to_string(mu));
  }
  if (count < 3) throw InputError("friction cone: expected at least 3 generators, got " + std::to_string(count));
  const Eigen::Vector3d n = normal / len;
  Eigen::Vector3d t1, t2;
  ContactTangents(n, &t1, &t2);
  Eigen::Matrix3Xd g(3, count);
  const double scale = 1.0 / std::sqrt(1.0 + mu * mu);
  for (int j = 0; j < count; ++j) {
    const double theta = 2.0 * M_PI * j / count;
    g.col(j) = (n + mu * (std::cos(theta) * t1 + std::sin(theta) * t2)) * scale;
  }
  return g;
}

double RobustnessPerGeneratorWeight(double mu, int count) { return count * mu / (1.0 + mu * mu); }

}  // namespace rbcp
