#include "rbcp/core/config_checks.h"

#include <cmath>
#include <sstream>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

std::string WithUnit(const std::string& what, const std::string& unit) {
  return unit.empty() ? what : what + " [" + unit + "]";
}

}  // namespace

std::string ConfigNumber(double value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

void ConfigChecks::Fail(const std::string& key, const std::string& expected, const std::string& got) const {
  throw InputError(where_ + ": '" + key + "': expected " + expected + ", got " + got);
}

void ConfigChecks::Positive(const std::string& key, double value, const std::string& unit) const {
  if (!(std::isfinite(value) && value > 0.0)) Fail(key, WithUnit("a positive number", unit), ConfigNumber(value));
}

void ConfigChecks::NonNegative(const std::string& key, double value, const std::string& unit) const {
  if (!(std::isfinite(value) && value >= 0.0)) Fail(key, WithUnit("a non-negative number", unit), ConfigNumber(value));
}

void ConfigChecks::Finite(const std::string& key, double value) const {
  if (!std::isfinite(value)) Fail(key, "a finite number", ConfigNumber(value));
}

void ConfigChecks::InRange(const std::string& key, double value, double lo, double hi, const std::string& unit) const {
  if (!(std::isfinite(value) && value >= lo && value <= hi)) {
    Fail(key, WithUnit("a number in [" + ConfigNumber(lo) + ", " + ConfigNumber(hi) + "]", unit), ConfigNumber(value));
  }
}

void ConfigChecks::AtLeast(const std::string& key, int value, int min) const {
  if (value < min) Fail(key, "an integer >= " + std::to_string(min), std::to_string(value));
}

void ConfigChecks::InRange(const std::string& key, int value, int lo, int hi) const {
  if (value < lo || value > hi) {
    Fail(key, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", std::to_string(value));
  }
}

}  // namespace rbcp
