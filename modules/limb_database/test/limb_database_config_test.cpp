#include <gtest/gtest.h>

#include <filesystem>

#include <cstdlib>

#include "limb_database_test_util.h"
#include "rbcp/core/error.h"
#include "rbcp/limb_database/limb_database.h"

namespace rbcp {
namespace {

YamlMap Parse(const std::string& text) { return YamlMap(YAML::Load(text), "test.yaml"); }

const char* kValid =
    "samples_per_leg: 1000\noctree_resolution: 0.02\nseed: 7\nweight_haa: 100\nweight_hfe: 1\n"
    "weight_kfe: 0.5\ncache_dir: /tmp/x\n";

TEST(LimbDatabaseConfig, TheShippedFileHoldsTheDefaultsThePapersValues) {
  const LimbDatabaseConfig c = LimbDatabaseConfig::LoadFile(test::ConfigDir() + "/limb_database.yaml");
  EXPECT_EQ(DifferingFields(c, LimbDatabaseConfig()), std::vector<std::string>{});
  EXPECT_EQ(c.samples_per_leg, 50000);
  EXPECT_DOUBLE_EQ(c.octree_resolution, 0.01);
  EXPECT_DOUBLE_EQ(c.weight_haa, 1.0);
  EXPECT_DOUBLE_EQ(c.weight_hfe, 1.0);
  EXPECT_DOUBLE_EQ(c.weight_kfe, 1.0);
}

TEST(LimbDatabaseConfig, ReadsEveryKey) {
  const LimbDatabaseConfig c = LimbDatabaseConfig::Load(Parse(kValid));
  EXPECT_EQ(c.samples_per_leg, 1000);
  EXPECT_DOUBLE_EQ(c.octree_resolution, 0.02);
  EXPECT_EQ(c.seed, 7u);
  EXPECT_DOUBLE_EQ(c.weight_haa, 100.0);
  EXPECT_DOUBLE_EQ(c.weight_hfe, 1.0);
  EXPECT_DOUBLE_EQ(c.weight_kfe, 0.5);
  EXPECT_EQ(c.cache_dir, "/tmp/x");
  EXPECT_EQ(c.ResolvedCacheDir(), "/tmp/x");
}

TEST(LimbDatabaseConfig, RejectsMissingUnknownAndOutOfRangeValues) {
  const std::string valid = kValid;
  EXPECT_THROW(LimbDatabaseConfig::Load(Parse(valid + "extra: 1\n")), InputError);
  EXPECT_THROW(LimbDatabaseConfig::Load(Parse("samples_per_leg: 1000\n")), InputError);
  auto with = [&](const std::string& key, const std::string& value) {
    std::string text;
    std::istringstream in(valid);
    for (std::string line; std::getline(in, line);) {
      text += (line.rfind(key + ":", 0) == 0 ? key + ": " + value : line) + "\n";
    }
    return Parse(text);
  };
  EXPECT_THROW(LimbDatabaseConfig::Load(with("samples_per_leg", "0")), InputError);
  EXPECT_THROW(LimbDatabaseConfig::Load(with("samples_per_leg", "many")), InputError);
  EXPECT_THROW(LimbDatabaseConfig::Load(with("octree_resolution", "0")), InputError);
  EXPECT_THROW(LimbDatabaseConfig::Load(with("octree_resolution", "2.0")), InputError);
  EXPECT_THROW(LimbDatabaseConfig::Load(with("seed", "-1")), InputError);
  EXPECT_THROW(LimbDatabaseConfig::Load(with("weight_hfe", "-1")), InputError);
  EXPECT_NO_THROW(LimbDatabaseConfig::Load(with("weight_hfe", "0")));
  try {
    LimbDatabaseConfig::Load(with("octree_resolution", "0.0001"));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("octree_resolution"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected"), std::string::npos) << e.what();
  }
  LimbDatabaseConfig zero;
  zero.weight_haa = zero.weight_hfe = zero.weight_kfe = 0.0;
  EXPECT_THROW(zero.Validate(), InputError);
}

TEST(LimbDatabaseConfig, DefaultCacheFolderFollowsXdg) {
  const char* old_xdg = std::getenv("XDG_CACHE_HOME");
  const std::string saved = old_xdg ? old_xdg : "";
  LimbDatabaseConfig c;
  ::setenv("XDG_CACHE_HOME", "/var/tmp/xdg", 1);
  EXPECT_EQ(c.ResolvedCacheDir(), "/var/tmp/xdg/rbcp/limb_database");
  ::unsetenv("XDG_CACHE_HOME");
  EXPECT_NE(c.ResolvedCacheDir().find("rbcp/limb_database"), std::string::npos);
  if (old_xdg) ::setenv("XDG_CACHE_HOME", saved.c_str(), 1);
}

TEST(LimbDatabaseConfig, WithoutHomeTheCacheNeverFallsBackToTheSharedTemporaryFolder) {
  const char* old_xdg = std::getenv("XDG_CACHE_HOME");
  const char* old_home = std::getenv("HOME");
  const std::string saved_xdg = old_xdg ? old_xdg : "", saved_home = old_home ? old_home : "";
  ::unsetenv("XDG_CACHE_HOME");
  ::unsetenv("HOME");
  const std::string dir = LimbDatabaseConfig{}.ResolvedCacheDir();
  ::setenv("XDG_CACHE_HOME", "relative/xdg", 1);  // ignored, as the XDG specification says
  const std::string relative = LimbDatabaseConfig{}.ResolvedCacheDir();
  if (old_xdg) ::setenv("XDG_CACHE_HOME", saved_xdg.c_str(), 1); else ::unsetenv("XDG_CACHE_HOME");
  if (old_home) ::setenv("HOME", saved_home.c_str(), 1);
  // The home folder of the password database, or no cache at all.
  const std::string temp = std::filesystem::temp_directory_path().string();
  EXPECT_NE(dir.rfind(temp, 0), 0u) << dir;
  if (!dir.empty()) {
    EXPECT_EQ(dir.front(), '/') << dir;
  }
  EXPECT_EQ(relative, dir);
}

}  // namespace
}  // namespace rbcp
