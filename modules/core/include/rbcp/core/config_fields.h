#pragma once
/// Configuration fields declared once. A configuration struct lists its fields, in the order of
/// its YAML file, in one member template:
///
///   template <class Visitor>
///   void Serialize(Visitor* v) {
///     v->Visit("path_step_s", &path_step_s, "s", bounds::Positive(), "root path step of the keep phase");
///     v->Visit("follow_feet", &follow_feet, "the base follows the plane of the stance feet");
///     v->Visit("workspace", &workspace, "where a foot may stand");  // a map: workspace's own Serialize
///     v->Map("limits", "...", [&](auto* m) { m->Visit("v_max", &limits.v_max, ...); });  // a map laid out here
///     v->Rule("box_max", box_max.x() > box_min.x(), "above box_min in x", ConfigNumber(box_max.x()));
///   }
///
/// Visit takes the key, the field, its unit ("" for none), its bounds (numbers, and every element
/// of a list of numbers) and a one-line meaning; bool, string and map fields (a struct with its own
/// Serialize, or a std::optional of one: a map the file may leave out) take the key, the field and
/// the meaning; an enum field takes the key, the field, the names of its values (EnumNames) and the
/// meaning. A Rule relates fields that bounds cannot. Everything else follows from that list:
///  - LoadConfig: reads a YamlMap strictly (every key required, no other accepted, maps nested),
///    then ValidateConfig;
///  - ValidateConfig: every bound and rule, errors as "<where>: '<key>': expected <what>, got <value>"
///    (a nested map's where is "<where>: <map key>", as YamlMap names it);
///  - DescribeConfig: one row per field (key, unit, bounds, value, meaning) for the documentation
///    page (docs/configuration.md) and for comparing two configurations (DifferingFields).
/// The visitors that only read (validation, description) call Serialize through a const_cast and
/// never write to the fields.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rbcp/core/config_checks.h"
#include "rbcp/core/yaml_reader.h"

namespace rbcp {

/// The values of an enum and their names in a configuration file.
template <class Enum>
using EnumNames = std::vector<std::pair<Enum, std::string>>;

/// "'centroid' or 'hip'": the names a file may give.
template <class Enum>
std::string OneOf(const EnumNames<Enum>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + ("'" + names[i].second + "'");
  }
  return text;
}

/// The name of `value` among `names` ("" when it has none).
template <class Enum>
std::string NameOf(Enum value, const EnumNames<Enum>& names) {
  for (const auto& [v, name] : names) {
    if (v == value) return name;
  }
  return "";
}

/// The value named `name` among `names`; std::nullopt when none has that name.
template <class Enum>
std::optional<Enum> ValueOf(const std::string& name, const EnumNames<Enum>& names) {
  for (const auto& [v, n] : names) {
    if (n == name) return v;
  }
  return std::nullopt;
}

/// Reads the fields a Serialize lists from a YamlMap (types, missing and unknown keys).
class ConfigLoader {
 public:
  explicit ConfigLoader(const YamlMap& map) : map_(map) {}

  template <class T>
  void Visit(const char* key, T* value, const char* /*unit*/, const Bounds& /*bounds*/, const char* /*meaning*/) {
    Read(key, value);
  }
  void Visit(const char* key, bool* value, const char* /*meaning*/) { *value = map_.Bool(key); }
  void Visit(const char* key, std::string* value, const char* /*meaning*/) { *value = map_.String(key); }
  template <class Enum>
  void Visit(const char* key, Enum* value, const EnumNames<Enum>& names, const char* /*meaning*/) {
    const std::string name = map_.String(key);
    const std::optional<Enum> named = ValueOf(name, names);
    if (!named) map_.Fail(key, "expected " + OneOf(names) + ", got '" + name + "'");
    *value = *named;
  }
  template <class Nested>
  void Visit(const char* key, Nested* nested, const char* meaning) {
    Map(key, meaning, [nested](auto* v) { nested->Serialize(v); });
  }
  template <class Nested>
  void Visit(const char* key, std::optional<Nested>* nested, const char* meaning) {
    nested->reset();
    if (!map_.Has(key)) return;
    Nested value;
    Visit(key, &value, meaning);
    *nested = value;
  }
  template <class Fields>
  void Map(const char* key, const char* /*meaning*/, Fields&& fields) {
    const YamlMap sub = map_.Map(key);
    ConfigLoader loader(sub);
    fields(&loader);
    sub.RejectUnknownKeys();
  }
  void Rule(const char* /*key*/, bool /*holds*/, const std::string& /*expected*/, const std::string& /*got*/) {}

 private:
  void Read(const char* key, double* value) { *value = map_.Double(key); }
  void Read(const char* key, int* value) { *value = map_.Int(key); }
  void Read(const char* key, unsigned* value) { *value = static_cast<unsigned>(NonNegativeInt(key)); }
  void Read(const char* key, std::uint64_t* value) { *value = static_cast<std::uint64_t>(NonNegativeInt(key)); }
  int NonNegativeInt(const char* key) const;
  void Read(const char* key, Eigen::Vector3d* value) { *value = map_.Vector3(key); }
  void Read(const char* key, std::vector<double>* value) { *value = map_.Numbers(key); }
  template <std::size_t N>
  void Read(const char* key, std::array<double, N>* value) {
    const Eigen::VectorXd v = map_.Vector(key, static_cast<int>(N));
    for (std::size_t i = 0; i < N; ++i) (*value)[i] = v[static_cast<int>(i)];
  }

  const YamlMap& map_;
};

/// Checks every bound and rule a Serialize lists; throws InputError at the first violation.
class ConfigValidator {
 public:
  explicit ConfigValidator(std::string where) : where_(std::move(where)), check_(where_) {}

  template <class T>
  void Visit(const char* key, T* value, const char* unit, const Bounds& bounds, const char* /*meaning*/) {
    Check(key, *value, unit, bounds);
  }
  void Visit(const char* /*key*/, bool* /*value*/, const char* /*meaning*/) {}
  void Visit(const char* /*key*/, std::string* /*value*/, const char* /*meaning*/) {}
  template <class Enum>
  void Visit(const char* key, Enum* value, const EnumNames<Enum>& names, const char* /*meaning*/) const {
    if (NameOf(*value, names).empty()) check_.Fail(key, OneOf(names), "a value without a name");
  }
  template <class Nested>
  void Visit(const char* key, Nested* nested, const char* meaning) {
    Map(key, meaning, [nested](auto* v) { nested->Serialize(v); });
  }
  template <class Nested>
  void Visit(const char* key, std::optional<Nested>* nested, const char* meaning) {
    if (*nested) Visit(key, &**nested, meaning);
  }
  template <class Fields>
  void Map(const char* key, const char* /*meaning*/, Fields&& fields) {
    ConfigValidator validator(where_ + ": " + key);
    fields(&validator);
  }
  void Rule(const char* key, bool holds, const std::string& expected, const std::string& got) const {
    if (!holds) check_.Fail(key, expected, got);
  }

 private:
  void Check(const std::string& key, double value, const char* unit, const Bounds& bounds) const {
    check_.Check(key, value, bounds, unit);
  }
  void Check(const std::string& key, int value, const char* unit, const Bounds& bounds) const {
    check_.CheckInteger(key, value, bounds, unit);
  }
  void Check(const std::string& key, unsigned value, const char* unit, const Bounds& bounds) const {
    check_.CheckInteger(key, value, bounds, unit);
  }
  void Check(const std::string& key, std::uint64_t value, const char* unit, const Bounds& bounds) const {
    check_.CheckInteger(key, static_cast<long long>(value), bounds, unit);
  }
  template <class List>
  void Check(const std::string& key, const List& list, const char* unit, const Bounds& bounds) const {
    for (std::size_t i = 0; i < static_cast<std::size_t>(list.size()); ++i) {
      check_.Check(key + "[" + std::to_string(i) + "]", list[static_cast<int>(i)], bounds, unit);
    }
  }

  std::string where_;
  ConfigChecks check_;
};

/// One field of a configuration as the documentation shows it.
struct ConfigField {
  std::string key;      ///< the path of keys: "workspace.max_forward_m"
  std::string unit;     ///< "m", "N m", ...; "-" for a number without unit; "" for the others
  std::string bounds;   ///< "> 0", "integer in [3, 64]", "3 numbers, each >= 0", "true or false", "text", "map"
  std::string value;    ///< exactly: "0.02", "[1, 0.5, 0, 1.5]", "true", "\"\""; "" for a map
  std::string meaning;
};

/// A relation between fields that the bounds do not express.
struct ConfigRule {
  std::string key;
  std::string expected;
};

struct ConfigDescription {
  std::vector<ConfigField> fields;
  std::vector<ConfigRule> rules;
};

/// Collects the fields and rules a Serialize lists, with their values.
class ConfigDescriber {
 public:
  explicit ConfigDescriber(ConfigDescription* out, std::string prefix = "") : out_(out), prefix_(std::move(prefix)) {}

  template <class T>
  void Visit(const char* key, T* value, const char* unit, const Bounds& bounds, const char* meaning) {
    Add(key, *unit ? unit : "-", Kind(*value, bounds), Value(*value), meaning);
  }
  void Visit(const char* key, bool* value, const char* meaning) {
    Add(key, "", "true or false", *value ? "true" : "false", meaning);
  }
  void Visit(const char* key, std::string* value, const char* meaning) {
    Add(key, "", "text", value->empty() ? "\"\"" : *value, meaning);
  }
  template <class Enum>
  void Visit(const char* key, Enum* value, const EnumNames<Enum>& names, const char* meaning) {
    Add(key, "", OneOf(names), NameOf(*value, names), meaning);
  }
  template <class Nested>
  void Visit(const char* key, Nested* nested, const char* meaning) {
    Map(key, meaning, [nested](auto* v) { nested->Serialize(v); });
  }
  /// An optional map: its fields with their values, or with the defaults of its type when absent.
  template <class Nested>
  void Visit(const char* key, std::optional<Nested>* nested, const char* meaning) {
    Nested shown = nested->value_or(Nested());
    const std::size_t map_row = out_->fields.size();
    Map(key, meaning, [&shown](auto* v) { shown.Serialize(v); });
    out_->fields[map_row].bounds = "map, may be left out";
    out_->fields[map_row].value = *nested ? "" : "(left out)";
  }
  template <class Fields>
  void Map(const char* key, const char* meaning, Fields&& fields) {
    Add(key, "", "map", "", meaning);
    ConfigDescriber describer(out_, prefix_ + key + ".");
    fields(&describer);
  }
  void Rule(const char* key, bool /*holds*/, const std::string& expected, const std::string& /*got*/) {
    out_->rules.push_back({prefix_ + key, expected});
  }

 private:
  void Add(const char* key, std::string unit, std::string bounds, std::string value, const char* meaning) {
    out_->fields.push_back({prefix_ + key, std::move(unit), std::move(bounds), std::move(value), meaning});
  }
  static std::string Kind(double, const Bounds& b) { return b.Text() == "any" ? "any number" : b.Text(); }
  static std::string Kind(int, const Bounds& b) { return b.Text() == "any" ? "integer" : "integer " + Phrase(b); }
  static std::string Kind(unsigned, const Bounds& b) { return Kind(0, b); }
  static std::string Kind(std::uint64_t, const Bounds& b) { return Kind(0, b); }
  template <class List>
  static std::string Kind(const List& list, const Bounds& b) {
    const std::string count = IsFixedSize(list) ? std::to_string(list.size()) + " numbers" : "list of numbers";
    return b.Text() == "any" ? count : count + ", each " + Phrase(b);
  }
  /// "in [0, 1]", "> 0": the bounds after a noun.
  static std::string Phrase(const Bounds& b) {
    const std::string text = b.Text();
    return text[0] == '[' || text[0] == '(' ? "in " + text : text;
  }
  static bool IsFixedSize(const std::vector<double>&) { return false; }
  template <class List>
  static bool IsFixedSize(const List&) { return true; }
  static std::string Value(double v) { return ExactNumber(v); }
  static std::string Value(int v) { return std::to_string(v); }
  static std::string Value(unsigned v) { return std::to_string(v); }
  static std::string Value(std::uint64_t v) { return std::to_string(v); }
  template <class List>
  static std::string Value(const List& list) {
    std::string text = "[";
    for (std::size_t i = 0; i < static_cast<std::size_t>(list.size()); ++i) {
      text += (i ? ", " : "") + ExactNumber(list[static_cast<int>(i)]);
    }
    return text + "]";
  }

  ConfigDescription* out_;
  std::string prefix_;
};

/// Throws InputError (naming `where` and the key) unless every field of `config` lies within its
/// bounds and every rule holds.
template <class Config>
void ValidateConfig(const Config& config, const std::string& where) {
  ConfigValidator validator(where);
  const_cast<Config&>(config).Serialize(&validator);
}

/// Every field Config::Serialize lists, read from `map` (every key required, no other accepted),
/// then validated; the other members keep their defaults. Throws InputError.
template <class Config>
Config LoadConfig(const YamlMap& map) {
  Config config;
  ConfigLoader loader(map);
  config.Serialize(&loader);
  map.RejectUnknownKeys();
  ValidateConfig(config, map.Where());
  return config;
}

/// The fields and rules of `config`, with its values.
template <class Config>
ConfigDescription DescribeConfig(const Config& config) {
  ConfigDescription description;
  ConfigDescriber describer(&description);
  const_cast<Config&>(config).Serialize(&describer);
  return description;
}

/// "key: value_a vs value_b" for every field whose value differs between a and b (exactly).
template <class Config>
std::vector<std::string> DifferingFields(const Config& a, const Config& b) {
  const std::vector<ConfigField> fa = DescribeConfig(a).fields;
  const std::vector<ConfigField> fb = DescribeConfig(b).fields;
  std::vector<std::string> out;
  for (std::size_t i = 0; i < fa.size() && i < fb.size(); ++i) {
    if (fa[i].value != fb[i].value) out.push_back(fa[i].key + ": " + fa[i].value + " vs " + fb[i].value);
  }
  return out;
}

/// The markdown table of a description (key, unit, bounds, default, meaning), then its rules.
std::string ConfigTable(const ConfigDescription& description);

}  // namespace rbcp
