#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

namespace fs = std::filesystem;

std::string Join(const Eigen::VectorXd& v) {
  std::ostringstream os;
  os << "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  os << "]";
  return os.str();
}

bool IsValidName(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

std::string ResolveMeshPath(const std::string& scenario_path, const std::string& file) {
  const fs::path p(file);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (fs::path(scenario_path).parent_path() / p).lexically_normal().string();
}

TerrainBox ReadBox(const YamlMap& m) {
  TerrainBox box;
  box.size = m.Vector3("size");
  box.position = m.Vector3("position");
  box.rpy = m.Vector3("rpy");
  m.RejectUnknownKeys();
  if ((box.size.array() <= 0.0).any()) m.Fail("size", "expected three positive lengths [m], got " + Join(box.size));
  return box;
}

TerrainMeshFile ReadMesh(const YamlMap& m, const std::string& scenario_path) {
  TerrainMeshFile mesh;
  mesh.file = m.String("file");
  mesh.position = m.Vector3("position");
  mesh.rpy = m.Vector3("rpy");
  mesh.scale = m.Double("scale");
  m.RejectUnknownKeys();
  if (mesh.file.empty()) m.Fail("file", "expected a mesh file path, got an empty string");
  if (!(mesh.scale > 0.0)) {
    std::ostringstream os;
    os << "expected a positive scale, got " << mesh.scale;
    m.Fail("scale", os.str());
  }
  mesh.resolved_path = ResolveMeshPath(scenario_path, mesh.file);
  return mesh;
}

TerrainElement ReadElement(const YamlMap& e, const std::string& scenario_path) {
  const std::vector<std::string> keys = e.Keys();
  if (keys.size() != 1) {
    e.Fail("", "expected exactly one of 'box' or 'mesh' per element, got " + std::to_string(keys.size()) + " keys");
  }
  if (keys[0] == "box") return ReadBox(e.Map("box"));
  if (keys[0] == "mesh") return ReadMesh(e.Map("mesh"), scenario_path);
  e.Fail(keys[0], "unknown key (expected 'box' or 'mesh')");
}

BaseGoal ReadBaseGoal(const YamlMap& m) {
  BaseGoal g;
  g.position = m.Vector2("position");
  g.yaw = m.Double("yaw");
  m.RejectUnknownKeys();
  return g;
}

void RequireTerrainBelow(const YamlMap& root, const std::string& key, const BaseGoal& g, const TriangleMesh& mesh) {
  if (!TerrainHeightAt(mesh, g.position)) {
    root.Fail(key, "expected terrain below the base position, got none at (" + std::to_string(g.position.x()) + ", " +
                       std::to_string(g.position.y()) + ")");
  }
}

/// Fixed-point with at most six decimals, trailing zeros removed, never "-0".
std::string FormatNumber(double v) {
  RBCP_CHECK(std::isfinite(v), "scenario numbers are finite");
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.6f", v);
  std::string s(buf);
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

std::string FormatVector(const Eigen::VectorXd& v) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? ", " : "") + FormatNumber(v[i]);
  return s + "]";
}

std::string Quoted(const std::string& s) {
  YAML::Emitter out;
  out << YAML::DoubleQuoted << s;
  return out.c_str();
}

std::string FormatBaseGoal(const BaseGoal& g) {
  return "{position: " + FormatVector(g.position) + ", yaw: " + FormatNumber(g.yaw) + "}";
}

}  // namespace

bool operator==(const BaseGoal& a, const BaseGoal& b) { return a.position == b.position && a.yaw == b.yaw; }

bool operator==(const TerrainBox& a, const TerrainBox& b) {
  return a.size == b.size && a.position == b.position && a.rpy == b.rpy;
}

bool operator==(const TerrainMeshFile& a, const TerrainMeshFile& b) {
  return a.file == b.file && a.resolved_path == b.resolved_path && a.position == b.position && a.rpy == b.rpy &&
         a.scale == b.scale;
}

TriangleMesh ElementMesh(const TerrainElement& element) {
  if (const auto* box = std::get_if<TerrainBox>(&element)) {
    TriangleMesh mesh = MakeBoxMesh(box->size);
    mesh.Transform(PoseFromRpy(box->position, box->rpy));
    return mesh;
  }
  const auto& file = std::get<TerrainMeshFile>(element);
  TriangleMesh mesh = LoadMeshFile(file.resolved_path, file.scale);
  mesh.Transform(PoseFromRpy(file.position, file.rpy));
  return mesh;
}

TriangleMesh BuildTerrainMesh(const std::vector<TerrainElement>& terrain) {
  TriangleMesh all;
  for (const auto& e : terrain) all.Append(ElementMesh(e));
  return all;
}

Scenario ParseScenario(const std::string& yaml_text, const std::string& path) {
  const std::string where = path.empty() ? std::string("<scenario text>") : path;
  const YamlMap root = YamlMap::Parse(yaml_text, where);

  Scenario s;
  s.path = path;
  s.name = root.String("name");
  if (!IsValidName(s.name)) root.Fail("name", "expected letters, digits, '_' or '-', got '" + s.name + "'");

  const std::vector<YamlMap> elements = root.MapList("terrain");
  if (elements.empty()) root.Fail("terrain", "expected at least one terrain element, got an empty list");
  for (const YamlMap& e : elements) {
    s.terrain.push_back(ReadElement(e, path));
    TriangleMesh mesh;
    try {
      mesh = ElementMesh(s.terrain.back());
    } catch (const InputError& err) {
      throw InputError(e.Where() + ": " + err.what());
    }
    const std::string problem = ValidateMesh(mesh);
    if (!problem.empty()) e.Fail("", "degenerate element mesh: " + problem);
    s.terrain_mesh.Append(mesh);
  }

  s.start = ReadBaseGoal(root.Map("start"));
  s.goal = ReadBaseGoal(root.Map("goal"));
  root.RejectUnknownKeys();

  RequireTerrainBelow(root, "start", s.start, s.terrain_mesh);
  RequireTerrainBelow(root, "goal", s.goal, s.terrain_mesh);
  return s;
}

Scenario LoadScenario(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open scenario file");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseScenario(text.str(), path);
}

std::string ScenarioToYaml(const Scenario& scenario, const std::vector<std::string>& header_comments) {
  std::string out;
  for (const auto& line : header_comments) out += "# " + line + "\n";
  out += "name: " + scenario.name + "\n";
  out += "terrain:\n";
  for (const auto& element : scenario.terrain) {
    if (const auto* box = std::get_if<TerrainBox>(&element)) {
      out += "  - box: {size: " + FormatVector(box->size) + ", position: " + FormatVector(box->position) +
             ", rpy: " + FormatVector(box->rpy) + "}\n";
    } else {
      const auto& mesh = std::get<TerrainMeshFile>(element);
      out += "  - mesh: {file: " + Quoted(mesh.file) + ", position: " + FormatVector(mesh.position) +
             ", rpy: " + FormatVector(mesh.rpy) + ", scale: " + FormatNumber(mesh.scale) + "}\n";
    }
  }
  out += "start: " + FormatBaseGoal(scenario.start) + "\n";
  out += "goal: " + FormatBaseGoal(scenario.goal) + "\n";
  return out;
}

BaseGoal ReadBasePose(const YamlMap& map) { return ReadBaseGoal(map); }

}  // namespace rbcp
