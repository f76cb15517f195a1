#pragma once
/// Strict YAML reading: every map is read through a YamlMap that knows where it came from
/// ("config/robots/anymal_b.yaml: leg_bounds.LF"), rejects missing and unknown keys, and
/// reports type errors as "expected X, got Y". Errors are rbcp::InputError.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <set>
#include <string>
#include <vector>

#include "rbcp/core/error.h"

namespace rbcp {

class YamlMap {
 public:
  /// `where` names the source, e.g. the file path plus the key path to this map.
  YamlMap(YAML::Node node, std::string where);

  /// Loads a file whose top level must be a map. Throws InputError naming the file.
  static YamlMap LoadFile(const std::string& path);
  /// The same from text; `where` names it in errors (a file's path, "<scenario text>").
  static YamlMap Parse(const std::string& yaml_text, const std::string& where);

  bool Has(const std::string& key) const;

  double Double(const std::string& key) const;
  double Double(const std::string& key, double fallback) const;
  int Int(const std::string& key) const;
  bool Bool(const std::string& key) const;
  std::string String(const std::string& key) const;
  /// A fixed-size list of finite numbers.
  Eigen::VectorXd Vector(const std::string& key, int size) const;
  /// A list of finite numbers of any length (possibly empty).
  std::vector<double> Numbers(const std::string& key) const;
  Eigen::Vector3d Vector3(const std::string& key) const { return Vector(key, 3); }
  Eigen::Vector2d Vector2(const std::string& key) const { return Vector(key, 2); }
  YamlMap Map(const std::string& key) const;
  /// A list of strings (possibly empty).
  std::vector<std::string> Strings(const std::string& key) const;
  /// A list of maps.
  std::vector<YamlMap> MapList(const std::string& key) const;
  /// Keys in document order.
  std::vector<std::string> Keys() const;

  /// Throws if the map holds a key that was never read (call after reading everything).
  void RejectUnknownKeys() const;

  const std::string& Where() const { return where_; }
  [[noreturn]] void Fail(const std::string& key, const std::string& problem) const;

 private:
  YAML::Node Required(const std::string& key) const;
  /// The finite numbers of a sequence node (errors name `key`).
  std::vector<double> NumbersOf(const YAML::Node& n, const std::string& key) const;
  YAML::Node node_;
  std::string where_;
  mutable std::set<std::string> read_;
};

}  // namespace rbcp
