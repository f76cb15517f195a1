#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/limb_database/limb_database.h"

namespace rbcp {
namespace {

std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

LimbDatabaseConfig LimbDatabaseConfig::Load(const YamlMap& map) {
  LimbDatabaseConfig c;
  c.samples_per_leg = map.Int("samples_per_leg");
  c.octree_resolution = map.Double("octree_resolution");
  const int seed = map.Int("seed");
  if (seed < 0) map.Fail("seed", "expected a non-negative integer, got " + std::to_string(seed));
  c.seed = static_cast<unsigned>(seed);
  c.weight_haa = map.Double("weight_haa");
  c.weight_hfe = map.Double("weight_hfe");
  c.weight_kfe = map.Double("weight_kfe");
  c.cache_dir = map.String("cache_dir");
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

LimbDatabaseConfig LimbDatabaseConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

void LimbDatabaseConfig::Validate(const std::string& where) const {
  auto fail = [&](const std::string& key, const std::string& expected, const std::string& got) {
    throw InputError(where + ": '" + key + "': expected " + expected + ", got " + got);
  };
  // Sample indices are stored as 32-bit integers; ten million per leg is far beyond any use.
  if (samples_per_leg < 1 || samples_per_leg > 10'000'000) {
    fail("samples_per_leg", "an integer in [1, 10000000]", std::to_string(samples_per_leg));
  }
  // The octree spans 65536 cells per axis around the base; 1 mm cells still cover +-32 m.
  if (!(std::isfinite(octree_resolution) && octree_resolution >= 0.001 && octree_resolution <= 0.5)) {
    fail("octree_resolution", "a number in [0.001, 0.5] [m]", Num(octree_resolution));
  }
  const double weights[3] = {weight_haa, weight_hfe, weight_kfe};
  const char* names[3] = {"weight_haa", "weight_hfe", "weight_kfe"};
  for (int j = 0; j < 3; ++j) {
    if (!(std::isfinite(weights[j]) && weights[j] >= 0.0)) fail(names[j], "a non-negative number", Num(weights[j]));
  }
  if (weight_haa + weight_hfe + weight_kfe <= 0.0) {
    fail("weight_haa + weight_hfe + weight_kfe", "a positive sum", Num(weight_haa + weight_hfe + weight_kfe));
  }
}

std::string LimbDatabaseConfig::ResolvedCacheDir() const {
  if (!cache_dir.empty()) return cache_dir;
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg && *xdg) return (std::filesystem::path(xdg) / "rbcp" / "limb_database").string();
  const char* home = std::getenv("HOME");
  if (home && *home) return (std::filesystem::path(home) / ".cache" / "rbcp" / "limb_database").string();
  return (std::filesystem::temp_directory_path() / "rbcp" / "limb_database").string();
}

}  // namespace rbcp
