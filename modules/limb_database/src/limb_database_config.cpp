#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "rbcp/core/config_checks.h"
#include "rbcp/limb_database/limb_database.h"

namespace rbcp {

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
  const ConfigChecks check(where);
  // Sample indices are stored as 32-bit integers; ten million per leg is far beyond any use.
  check.InRange("samples_per_leg", samples_per_leg, 1, 10'000'000);
  // The octree spans 65536 cells per axis around the base; 1 mm cells still cover +-32 m.
  check.InRange("octree_resolution", octree_resolution, 0.001, 0.5, "m");
  check.NonNegative("weight_haa", weight_haa);
  check.NonNegative("weight_hfe", weight_hfe);
  check.NonNegative("weight_kfe", weight_kfe);
  if (weight_haa + weight_hfe + weight_kfe <= 0.0) {
    check.Fail("weight_haa + weight_hfe + weight_kfe", "a positive sum",
               ConfigNumber(weight_haa + weight_hfe + weight_kfe));
  }
}

std::string LimbDatabaseConfig::ResolvedCacheDir() const {
  if (!cache_dir.empty()) return cache_dir;
  const std::filesystem::path sub = std::filesystem::path("rbcp") / "limb_database";
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  // The XDG base directory specification ignores a relative XDG_CACHE_HOME.
  if (xdg && *xdg == '/') return (std::filesystem::path(xdg) / sub).string();
  const char* home = std::getenv("HOME");
  if (home && *home) return (std::filesystem::path(home) / ".cache" / sub).string();
  // The user's home folder from the password database; never a shared temporary folder, where
  // another user could plant a folder or links for this one.
  std::vector<char> buffer(16384);
  struct passwd entry {};
  struct passwd* found = nullptr;
  if (::getpwuid_r(::geteuid(), &entry, buffer.data(), buffer.size(), &found) == 0 && found && found->pw_dir &&
      found->pw_dir[0] == '/') {
    return (std::filesystem::path(found->pw_dir) / ".cache" / sub).string();
  }
  return "";
}

}  // namespace rbcp
