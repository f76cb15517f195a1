#include "rbcp/affordance/affordance_config.h"

#include <cmath>
#include <sstream>

namespace rbcp {
namespace {

struct FieldProblem {
  std::string key;   ///< empty when the config is valid
  std::string text;  ///< "expected X, got Y"
};

std::string Number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

FieldProblem FindProblem(const AffordanceConfig& c) {
  const auto angle = [](const char* key, double v) -> FieldProblem {
    if (std::isfinite(v) && v > 0.0 && v < 90.0) return {};
    return {key, "expected an angle in (0, 90) deg, got " + Number(v)};
  };
  if (auto p = angle("max_inclination_deg", c.max_inclination_deg); !p.key.empty()) return p;
  if (auto p = angle("neighbour_angle_deg", c.neighbour_angle_deg); !p.key.empty()) return p;
  if (!(std::isfinite(c.min_area) && c.min_area >= 0.0)) {
    return {"min_area", "expected an area >= 0 m^2, got " + Number(c.min_area)};
  }
  if (!(std::isfinite(c.edge_margin) && c.edge_margin >= 0.0)) {
    return {"edge_margin", "expected a distance >= 0 m, got " + Number(c.edge_margin)};
  }
  return {};
}

}  // namespace

AffordanceConfig AffordanceConfig::Load(const YamlMap& map) {
  AffordanceConfig c;
  c.max_inclination_deg = map.Double("max_inclination_deg");
  c.neighbour_angle_deg = map.Double("neighbour_angle_deg");
  c.min_area = map.Double("min_area");
  c.edge_margin = map.Double("edge_margin");
  map.RejectUnknownKeys();
  const FieldProblem p = FindProblem(c);
  if (!p.key.empty()) map.Fail(p.key, p.text);
  return c;
}

AffordanceConfig AffordanceConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

std::string AffordanceConfig::Problem() const {
  const FieldProblem p = FindProblem(*this);
  return p.key.empty() ? std::string() : "'" + p.key + "': " + p.text;
}

}  // namespace rbcp
