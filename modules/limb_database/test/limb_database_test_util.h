#pragma once
// Shared helpers of the limb database tests.

#include <cstdlib>
#include <filesystem>
#include <string>

#include "rbcp/limb_database/limb_database.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp::test {

inline std::string ConfigDir() { return std::string(RBCP_SOURCE_DIR) + "/config"; }

/// The shipped ANYmal B model, loaded once per test program.
inline const RobotModel& Anymal() {
  static const RobotModel model = RobotModel::LoadDefault(ConfigDir());
  return model;
}

/// The shipped configuration with fewer samples, writing its cache to `cache_dir`.
inline LimbDatabaseConfig SmallConfig(int samples = 5000, const std::string& cache_dir = "") {
  LimbDatabaseConfig c = LimbDatabaseConfig::LoadFile(ConfigDir() + "/limb_database.yaml");
  c.samples_per_leg = samples;
  c.cache_dir = cache_dir;
  return c;
}

/// A fresh folder, removed with its content when the object goes out of scope.
class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "rbcp_limb_db_test_XXXXXX").string();
    char* made = ::mkdtemp(pattern.data());
    if (made == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = made;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace rbcp::test
