#include "rbcp/core/yaml_reader.h"

#include <cmath>
#include <sstream>

namespace rbcp {
namespace {

std::string Describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null: return "nothing";
    case YAML::NodeType::Scalar: return "'" + n.Scalar() + "'";
    case YAML::NodeType::Sequence: return "a list of " + std::to_string(n.size());
    case YAML::NodeType::Map: return "a map";
    default: return "an undefined value";
  }
}

}  // namespace

YamlMap::YamlMap(YAML::Node node, std::string where) : node_(std::move(node)), where_(std::move(where)) {
  if (!node_.IsMap()) throw InputError(where_ + ": expected a map, got " + Describe(node_));
}

YamlMap YamlMap::LoadFile(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path + ": cannot open file");
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": invalid YAML: " + e.what());
  }
  return YamlMap(root, path);
}

YamlMap YamlMap::Parse(const std::string& yaml_text, const std::string& where) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(where + ": invalid YAML: " + e.what());
  }
  return YamlMap(root, where);
}

void YamlMap::Fail(const std::string& key, const std::string& problem) const {
  throw InputError(where_ + (key.empty() ? "" : ": '" + key + "'") + ": " + problem);
}

bool YamlMap::Has(const std::string& key) const { return static_cast<bool>(node_[key]); }

YAML::Node YamlMap::Required(const std::string& key) const {
  YAML::Node n = node_[key];
  if (!n) Fail(key, "missing key");
  read_.insert(key);
  return n;
}

double YamlMap::Double(const std::string& key) const {
  YAML::Node n = Required(key);
  double v = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) Fail(key, "expected a number, got " + Describe(n));
  if (!std::isfinite(v)) Fail(key, "expected a finite number, got " + n.Scalar());
  return v;
}

double YamlMap::Double(const std::string& key, double fallback) const { return Has(key) ? Double(key) : fallback; }

int YamlMap::Int(const std::string& key) const {
  YAML::Node n = Required(key);
  int v = 0;
  if (!n.IsScalar() || !YAML::convert<int>::decode(n, v)) Fail(key, "expected an integer, got " + Describe(n));
  return v;
}

bool YamlMap::Bool(const std::string& key) const {
  YAML::Node n = Required(key);
  bool v = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) Fail(key, "expected true or false, got " + Describe(n));
  return v;
}

std::string YamlMap::String(const std::string& key) const {
  YAML::Node n = Required(key);
  if (!n.IsScalar()) Fail(key, "expected a string, got " + Describe(n));
  return n.Scalar();
}

std::vector<std::string> YamlMap::Strings(const std::string& key) const {
  YAML::Node n = Required(key);
  if (!n.IsSequence()) Fail(key, "expected a list of strings, got " + Describe(n));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (!n[i].IsScalar()) Fail(key, "element " + std::to_string(i) + ": expected a string, got " + Describe(n[i]));
    out.push_back(n[i].Scalar());
  }
  return out;
}

std::vector<double> YamlMap::NumbersOf(const YAML::Node& n, const std::string& key) const {
  std::vector<double> v(n.size());
  for (std::size_t i = 0; i < n.size(); ++i) {
    double x = 0.0;
    const YAML::Node e = n[i];
    if (!e.IsScalar() || !YAML::convert<double>::decode(e, x)) {
      Fail(key, "element " + std::to_string(i) + ": expected a number, got " + Describe(e));
    }
    if (!std::isfinite(x)) Fail(key, "element " + std::to_string(i) + ": expected a finite number, got " + e.Scalar());
    v[i] = x;
  }
  return v;
}

std::vector<double> YamlMap::Numbers(const std::string& key) const {
  const YAML::Node n = Required(key);
  if (!n.IsSequence()) Fail(key, "expected a list of numbers, got " + Describe(n));
  return NumbersOf(n, key);
}

Eigen::VectorXd YamlMap::Vector(const std::string& key, int size) const {
  const YAML::Node n = Required(key);
  if (!n.IsSequence() || static_cast<int>(n.size()) != size) {
    Fail(key, "expected a list of " + std::to_string(size) + " numbers, got " + Describe(n));
  }
  const std::vector<double> v = NumbersOf(n, key);
  return Eigen::Map<const Eigen::VectorXd>(v.data(), size);
}

YamlMap YamlMap::Map(const std::string& key) const {
  YAML::Node n = Required(key);
  if (!n.IsMap()) Fail(key, "expected a map, got " + Describe(n));
  return YamlMap(n, where_ + ": " + key);
}

std::vector<YamlMap> YamlMap::MapList(const std::string& key) const {
  YAML::Node n = Required(key);
  if (!n.IsSequence()) Fail(key, "expected a list, got " + Describe(n));
  std::vector<YamlMap> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (!n[i].IsMap()) Fail(key, "element " + std::to_string(i) + ": expected a map, got " + Describe(n[i]));
    out.emplace_back(n[i], where_ + ": " + key + "[" + std::to_string(i) + "]");
  }
  return out;
}

std::vector<std::string> YamlMap::Keys() const {
  std::vector<std::string> keys;
  for (const auto& kv : node_) {
    // A key may be any YAML value ({[1, 2]: x}, or none at all: "&a : x"); the readers name keys.
    if (!kv.first.IsScalar()) Fail("", "expected keys that are strings, got a key that is " + Describe(kv.first));
    keys.push_back(kv.first.Scalar());
  }
  return keys;
}

void YamlMap::RejectUnknownKeys() const {
  for (const auto& key : Keys()) {
    if (!read_.count(key)) Fail(key, "unknown key");
  }
}

}  // namespace rbcp
