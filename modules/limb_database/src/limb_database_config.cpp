#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "rbcp/limb_database/limb_database.h"

namespace rbcp {

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
