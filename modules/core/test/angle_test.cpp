#include "rbcp/core/angle.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rbcp {
namespace {

TEST(WrapAngleTest, MapsIntoHalfOpenInterval) {
  EXPECT_NEAR(WrapAngle(0.5), 0.5, 1e-15);
  EXPECT_NEAR(WrapAngle(2.0 * M_PI + 0.5), 0.5, 1e-12);
  EXPECT_NEAR(WrapAngle(-M_PI), M_PI, 1e-15);
  EXPECT_NEAR(WrapAngle(M_PI), M_PI, 1e-15);
  EXPECT_NEAR(WrapAngle(-3.0 * M_PI / 2.0), M_PI / 2.0, 1e-12);
}

}  // namespace
}  // namespace rbcp
