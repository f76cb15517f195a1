#pragma once
/// Range checks shared by the configuration loaders, with one error format:
/// InputError("<where>: '<key>': expected <what>, got <value>").

#include <string>
#include <utility>

namespace rbcp {

/// A number as configuration errors print it: the default stream form ("0.3", "1e-05", "nan").
std::string ConfigNumber(double value);

class ConfigChecks {
 public:
  /// `where` names the configuration (usually the file), as YamlMap::Where() does.
  explicit ConfigChecks(std::string where) : where_(std::move(where)) {}

  [[noreturn]] void Fail(const std::string& key, const std::string& expected, const std::string& got) const;

  /// Finite and > 0: "a positive number", followed by " [unit]" when a unit is given.
  void Positive(const std::string& key, double value, const std::string& unit = "") const;
  /// Finite and >= 0: "a non-negative number" [unit].
  void NonNegative(const std::string& key, double value, const std::string& unit = "") const;
  /// "a finite number".
  void Finite(const std::string& key, double value) const;
  /// Finite and in [lo, hi]: "a number in [lo, hi]" [unit].
  void InRange(const std::string& key, double value, double lo, double hi, const std::string& unit = "") const;
  /// "an integer >= min".
  void AtLeast(const std::string& key, int value, int min) const;
  /// "an integer in [lo, hi]".
  void InRange(const std::string& key, int value, int lo, int hi) const;

 private:
  std::string where_;
};

}  // namespace rbcp
