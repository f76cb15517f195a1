#include "rbcp/core/config_dir.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace rbcp {

std::string DefaultConfigDir() {
  if (const char* env = std::getenv("RBCP_CONFIG_DIR"); env && *env) return env;
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "rbcp" / "config";
    if (std::filesystem::is_directory(installed / "robots", error)) return installed.string();
  }
  return RBCP_SOURCE_CONFIG_DIR;
}

}  // namespace rbcp
