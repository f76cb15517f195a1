#pragma once
/// The bounds of configuration values, and the one format of their errors:
/// InputError("<where>: '<key>': expected <what> [<unit>], got <value>").

#include <optional>
#include <string>
#include <utility>

namespace rbcp {

/// A number as configuration errors print it: the default stream form ("0.3", "1e-05", "nan").
std::string ConfigNumber(double value);
/// The shortest decimal form that reads back as exactly `value` ("0.1", "0.000833333333333").
std::string ExactNumber(double value);

/// The values a configuration number may take: finite, and within an interval whose ends are
/// open or closed, absent, or the value of another field (named in errors and documentation).
/// Built with the functions of namespace `bounds` and the chaining members below, e.g.
/// bounds::Positive().AtMost(path_step_s, "path_step_s") for (0, path_step_s].
class Bounds {
 public:
  Bounds Above(double value, std::string name = "") const { return WithLow({value, false, std::move(name)}); }
  Bounds AtLeast(double value, std::string name = "") const { return WithLow({value, true, std::move(name)}); }
  Bounds Below(double value, std::string name = "") const { return WithHigh({value, false, std::move(name)}); }
  Bounds AtMost(double value, std::string name = "") const { return WithHigh({value, true, std::move(name)}); }

  bool Holds(double value) const;
  /// What a value must be, as errors say it: "a positive number", "an integer in [3, 64]",
  /// "a number in (0, path_step_s] [s] (path_step_s = 0.02)". `unit` may be empty.
  std::string Expected(bool integer, const std::string& unit = "") const;
  /// As the documentation shows it: "> 0", "[3, 64]", "(0, path_step_s]", "any".
  std::string Text() const;

 private:
  struct End {
    double value = 0.0;
    bool inclusive = true;
    std::string name;  ///< the field whose value this is; empty for a constant
  };
  Bounds WithLow(End end) const;
  Bounds WithHigh(End end) const;
  std::string EndText(const End& end) const;

  std::optional<End> low_;
  std::optional<End> high_;
};

namespace bounds {
inline Bounds Any() { return Bounds(); }
inline Bounds Positive() { return Bounds().Above(0.0); }
inline Bounds NonNegative() { return Bounds().AtLeast(0.0); }
inline Bounds AtLeast(double low) { return Bounds().AtLeast(low); }
/// [low, high]
inline Bounds Closed(double low, double high) { return Bounds().AtLeast(low).AtMost(high); }
/// (low, high)
inline Bounds Open(double low, double high) { return Bounds().Above(low).Below(high); }
}  // namespace bounds

class ConfigChecks {
 public:
  /// `where` names the configuration (usually the file), as YamlMap::Where() does.
  explicit ConfigChecks(std::string where) : where_(std::move(where)) {}

  [[noreturn]] void Fail(const std::string& key, const std::string& expected, const std::string& got) const;

  /// Throws unless `value` lies within `bounds` ("expected a number in [0, 1] [m], got 2").
  void Check(const std::string& key, double value, const Bounds& bounds, const std::string& unit = "") const;
  /// The same for an integer ("expected an integer >= 1, got 0").
  void CheckInteger(const std::string& key, long long value, const Bounds& bounds, const std::string& unit = "") const;
  /// Finite and in [lo, hi].
  void InRange(const std::string& key, double value, double lo, double hi, const std::string& unit = "") const {
    Check(key, value, bounds::Closed(lo, hi), unit);
  }
  void InRange(const std::string& key, int value, int lo, int hi) const {
    CheckInteger(key, value, bounds::Closed(lo, hi));
  }

 private:
  std::string where_;
};

}  // namespace rbcp
