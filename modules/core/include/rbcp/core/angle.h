#pragma once
/// Angles.

#include <cmath>

namespace rbcp {

/// `a` [rad] wrapped into (-pi, pi].
inline double WrapAngle(double a) {
  a = std::remainder(a, 2.0 * M_PI);  // in [-pi, pi]
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

}  // namespace rbcp
