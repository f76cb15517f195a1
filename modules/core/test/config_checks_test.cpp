#include "rbcp/core/config_checks.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "rbcp/core/error.h"
#include "rbcp/test_support/error_of.h"

namespace rbcp {
namespace {

using rbcp::test_support::ErrorOf;

TEST(ConfigChecksTest, PassingValuesThrowNothing) {
  const ConfigChecks check("cfg.yaml");
  EXPECT_NO_THROW(check.Positive("a", 0.1));
  EXPECT_NO_THROW(check.NonNegative("a", 0.0));
  EXPECT_NO_THROW(check.Finite("a", -3.0));
  EXPECT_NO_THROW(check.InRange("a", 1.0, 0.0, 1.0));
  EXPECT_NO_THROW(check.AtLeast("n", 2, 2));
  EXPECT_NO_THROW(check.InRange("n", 64, 3, 64));
}

TEST(ConfigChecksTest, FailuresNameTheKeyTheExpectationAndTheValue) {
  const ConfigChecks check("cfg.yaml");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ErrorOf([&] { check.Positive("friction", 0.0); }), "cfg.yaml: 'friction': expected a positive number, got 0");
  EXPECT_EQ(ErrorOf([&] { check.NonNegative("margin", -0.01, "m"); }),
            "cfg.yaml: 'margin': expected a non-negative number [m], got -0.01");
  EXPECT_EQ(ErrorOf([&] { check.NonNegative("margin", nan); }),
            "cfg.yaml: 'margin': expected a non-negative number, got nan");
  EXPECT_EQ(ErrorOf([&] { check.Finite("h", std::numeric_limits<double>::infinity()); }),
            "cfg.yaml: 'h': expected a finite number, got inf");
  EXPECT_EQ(ErrorOf([&] { check.InRange("r", 0.6, 0.001, 0.5, "m"); }),
            "cfg.yaml: 'r': expected a number in [0.001, 0.5] [m], got 0.6");
  EXPECT_EQ(ErrorOf([&] { check.AtLeast("n", 0, 1); }), "cfg.yaml: 'n': expected an integer >= 1, got 0");
  EXPECT_EQ(ErrorOf([&] { check.InRange("g", 2, 3, 64); }), "cfg.yaml: 'g': expected an integer in [3, 64], got 2");
  EXPECT_EQ(ErrorOf([&] { check.Fail("k", "something", "else"); }), "cfg.yaml: 'k': expected something, got else");
}

}  // namespace
}  // namespace rbcp
