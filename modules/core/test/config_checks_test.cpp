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
  EXPECT_NO_THROW(check.Check("a", 0.1, bounds::Positive()));
  EXPECT_NO_THROW(check.Check("a", 0.0, bounds::NonNegative()));
  EXPECT_NO_THROW(check.Check("a", -3.0, bounds::Any()));
  EXPECT_NO_THROW(check.InRange("a", 1.0, 0.0, 1.0));
  EXPECT_NO_THROW(check.CheckInteger("n", 2, bounds::AtLeast(2)));
  EXPECT_NO_THROW(check.InRange("n", 64, 3, 64));
}

TEST(ConfigChecksTest, FailuresNameTheKeyTheExpectationAndTheValue) {
  const ConfigChecks check("cfg.yaml");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ErrorOf([&] { check.Check("friction", 0.0, bounds::Positive()); }),
            "cfg.yaml: 'friction': expected a positive number, got 0");
  EXPECT_EQ(ErrorOf([&] { check.Check("margin", -0.01, bounds::NonNegative(), "m"); }),
            "cfg.yaml: 'margin': expected a non-negative number [m], got -0.01");
  EXPECT_EQ(ErrorOf([&] { check.Check("margin", nan, bounds::NonNegative()); }),
            "cfg.yaml: 'margin': expected a non-negative number, got nan");
  EXPECT_EQ(ErrorOf([&] { check.Check("h", std::numeric_limits<double>::infinity(), bounds::Any()); }),
            "cfg.yaml: 'h': expected a finite number, got inf");
  EXPECT_EQ(ErrorOf([&] { check.InRange("r", 0.6, 0.001, 0.5, "m"); }),
            "cfg.yaml: 'r': expected a number in [0.001, 0.5] [m], got 0.6");
  EXPECT_EQ(ErrorOf([&] { check.Check("a", 90.0, bounds::Open(0, 90), "deg"); }),
            "cfg.yaml: 'a': expected a number in (0, 90) [deg], got 90");
  EXPECT_EQ(ErrorOf([&] { check.CheckInteger("n", 0, bounds::AtLeast(1)); }),
            "cfg.yaml: 'n': expected an integer >= 1, got 0");
  EXPECT_EQ(ErrorOf([&] { check.InRange("g", 2, 3, 64); }), "cfg.yaml: 'g': expected an integer in [3, 64], got 2");
  EXPECT_EQ(ErrorOf([&] { check.Fail("k", "something", "else"); }), "cfg.yaml: 'k': expected something, got else");
}

TEST(ConfigChecksTest, BoundsMayBeOtherFields) {
  const ConfigChecks check("cfg.yaml");
  const Bounds b = bounds::Positive().AtMost(0.02, "path_step_s");
  EXPECT_EQ(b.Text(), "(0, path_step_s]");
  EXPECT_TRUE(b.Holds(0.02));
  EXPECT_FALSE(b.Holds(0.021));
  EXPECT_EQ(ErrorOf([&] { check.Check("step", 0.5, b, "s"); }),
            "cfg.yaml: 'step': expected a number in (0, path_step_s] [s] (path_step_s = 0.02), got 0.5");
}

TEST(ConfigChecksTest, BoundsAsTheDocumentationShowsThem) {
  EXPECT_EQ(bounds::Any().Text(), "any");
  EXPECT_EQ(bounds::Positive().Text(), "> 0");
  EXPECT_EQ(bounds::NonNegative().Below(0.1).Text(), "[0, 0.1)");
  EXPECT_EQ(bounds::AtLeast(1).Text(), ">= 1");
  EXPECT_EQ(bounds::Any().AtMost(1).Text(), "<= 1");
}

TEST(ConfigChecksTest, ExactNumbersReadBackExactly) {
  EXPECT_EQ(ExactNumber(0.1), "0.1");
  EXPECT_EQ(ExactNumber(50.0), "50");
  EXPECT_EQ(ExactNumber(0.000833333333333), "0.000833333333333");
  EXPECT_EQ(ExactNumber(1.0 / 1200.0), "0.0008333333333333334");
  EXPECT_EQ(ExactNumber(-0.12), "-0.12");
}

}  // namespace
}  // namespace rbcp
