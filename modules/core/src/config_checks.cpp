#include "rbcp/core/config_checks.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "rbcp/core/error.h"

namespace rbcp {

std::string ConfigNumber(double value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

std::string ExactNumber(double value) {
  char text[64];
  const std::to_chars_result r = std::to_chars(text, text + sizeof(text), value);
  return std::string(text, r.ptr);
}

Bounds Bounds::WithLow(End end) const {
  Bounds b = *this;
  b.low_ = std::move(end);
  return b;
}

Bounds Bounds::WithHigh(End end) const {
  Bounds b = *this;
  b.high_ = std::move(end);
  return b;
}

bool Bounds::Holds(double value) const {
  if (!std::isfinite(value)) return false;
  if (low_ && !(low_->inclusive ? value >= low_->value : value > low_->value)) return false;
  if (high_ && !(high_->inclusive ? value <= high_->value : value < high_->value)) return false;
  return true;
}

std::string Bounds::EndText(const End& end) const { return end.name.empty() ? ConfigNumber(end.value) : end.name; }

std::string Bounds::Text() const {
  if (low_ && high_) {
    return (low_->inclusive ? "[" : "(") + EndText(*low_) + ", " + EndText(*high_) + (high_->inclusive ? "]" : ")");
  }
  if (low_) return (low_->inclusive ? ">= " : "> ") + EndText(*low_);
  if (high_) return (high_->inclusive ? "<= " : "< ") + EndText(*high_);
  return "any";
}

std::string Bounds::Expected(bool integer, const std::string& unit) const {
  const std::string noun = integer ? "integer" : "number";
  std::string what;
  if (!low_ && !high_) {
    what = integer ? "an integer" : "a finite number";
  } else if (low_ && !high_ && low_->name.empty() && low_->value == 0.0) {
    what = (low_->inclusive ? "a non-negative " : "a positive ") + noun;
  } else {
    what = (integer ? "an integer " : "a number ") + std::string(low_ && high_ ? "in " : "") + Text();
  }
  if (!unit.empty()) what += " [" + unit + "]";
  std::string named;
  for (const std::optional<End>& end : {low_, high_}) {
    if (!end || end->name.empty()) continue;
    named += (named.empty() ? "" : ", ") + end->name + " = " + ConfigNumber(end->value);
  }
  return named.empty() ? what : what + " (" + named + ")";
}

void ConfigChecks::Fail(const std::string& key, const std::string& expected, const std::string& got) const {
  throw InputError(where_ + ": '" + key + "': expected " + expected + ", got " + got);
}

void ConfigChecks::Check(const std::string& key, double value, const Bounds& bounds, const std::string& unit) const {
  if (!bounds.Holds(value)) Fail(key, bounds.Expected(false, unit), ConfigNumber(value));
}

void ConfigChecks::CheckInteger(const std::string& key, long long value, const Bounds& bounds,
                                const std::string& unit) const {
  if (!bounds.Holds(static_cast<double>(value))) Fail(key, bounds.Expected(true, unit), std::to_string(value));
}

}  // namespace rbcp
