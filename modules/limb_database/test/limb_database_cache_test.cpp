#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cache_format.h"
#include "limb_database_test_util.h"
#include "rbcp/core/error.h"
#include "rbcp/limb_database/limb_database.h"

namespace rbcp {
namespace {

namespace fs = std::filesystem;
using test::Anymal;
using test::ScratchDir;
using test::SmallConfig;

constexpr int kSamples = 1500;

std::vector<std::string> RobotFiles() { return LimbDatabase::DefaultRobotFiles(test::ConfigDir()); }

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Rewrites the payload checksum so that only the structural checks can reject the file.
void FixChecksum(std::string* bytes) {
  using namespace limb_database_detail;
  const std::uint64_t h = Hash64(bytes->data() + kCacheHeaderBytes, bytes->size() - kCacheHeaderBytes);
  std::memcpy(bytes->data() + kCacheChecksumOffset, &h, sizeof(h));
}

void ExpectSameDatabase(const LimbDatabase& a, const LimbDatabase& b) {
  EXPECT_EQ(a.Resolution(), b.Resolution());
  for (Leg leg : kAllLegs) {
    ASSERT_EQ(a.NumSamples(leg), b.NumSamples(leg));
    ASSERT_EQ(a.NumCells(leg), b.NumCells(leg));
    EXPECT_EQ(a.Draws(leg), b.Draws(leg));
    for (int i = 0; i < a.NumSamples(leg); ++i) {
      const LimbSample sa = a.Sample(leg, i), sb = b.Sample(leg, i);
      ASSERT_EQ(sa.q, sb.q);
      ASSERT_EQ(sa.foot_B, sb.foot_B);
      ASSERT_EQ(sa.score, sb.score);
      ASSERT_EQ(a.CellIndexAt(leg, sa.foot_B), b.CellIndexAt(leg, sb.foot_B));
    }
    for (int c = 0; c < a.NumCells(leg); ++c) {
      ASSERT_EQ(a.Cell(leg, c).centre_B, b.Cell(leg, c).centre_B);
      ASSERT_EQ(a.Cell(leg, c).first_sample, b.Cell(leg, c).first_sample);
      ASSERT_EQ(a.Cell(leg, c).num_samples, b.Cell(leg, c).num_samples);
    }
    // The rebuilt octree answers queries like the original.
    const Eigen::Vector3d foot = Anymal().ReferenceFootPosition(leg);
    const ConvexSurface square{{foot + Eigen::Vector3d(-0.1, -0.1, 0), foot + Eigen::Vector3d(0.1, -0.1, 0),
                                foot + Eigen::Vector3d(0.1, 0.1, 0), foot + Eigen::Vector3d(-0.1, 0.1, 0)},
                               Eigen::Vector3d::UnitZ()};
    const auto ca = a.Candidates(leg, Eigen::Isometry3d::Identity(), square, 0.02);
    const auto cb = b.Candidates(leg, Eigen::Isometry3d::Identity(), square, 0.02);
    ASSERT_EQ(ca.size(), cb.size());
    EXPECT_FALSE(ca.empty());
    for (std::size_t i = 0; i < ca.size(); ++i) EXPECT_EQ(ca[i].sample, cb[i].sample);
  }
}

std::vector<std::string> FilesIn(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(LimbDatabaseCache, SaveThenLoadGivesIdenticalData) {
  ScratchDir dir;
  const LimbDatabase built = LimbDatabase::Build(Anymal(), SmallConfig(kSamples));
  const std::string path = dir.path() + "/sub/db.bin";
  built.Save(path, 42);
  std::string reason;
  const std::optional<LimbDatabase> loaded = LimbDatabase::Load(path, 42, &reason);
  ASSERT_TRUE(loaded) << reason;
  EXPECT_TRUE(reason.empty());
  ExpectSameDatabase(built, *loaded);
  // Only the final file remains: the temporary one was renamed.
  EXPECT_EQ(FilesIn(dir.path() + "/sub"), std::vector<std::string>{"db.bin"});
  // Another key is refused.
  EXPECT_FALSE(LimbDatabase::Load(path, 43, &reason));
  EXPECT_NE(reason.find("key"), std::string::npos) << reason;
}

mode_t ModeOf(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::lstat(path.c_str(), &st), 0) << path;
  return st.st_mode & 07777;
}

TEST(LimbDatabaseCache, TheFolderIsPrivateAndNoLinkIsFollowed) {
  ScratchDir dir;
  const LimbDatabase built = LimbDatabase::Build(Anymal(), SmallConfig(kSamples));
  const std::string path = dir.path() + "/a/b/db.bin";
  built.Save(path, 42);
  EXPECT_EQ(ModeOf(dir.path() + "/a"), 0700u);
  EXPECT_EQ(ModeOf(dir.path() + "/a/b"), 0700u);
  EXPECT_EQ(ModeOf(path) & 077u, 0u) << "the file is the owner's only";
  std::string reason;
  ASSERT_TRUE(LimbDatabase::Load(path, 42, &reason)) << reason;

  // A cache file that is a symbolic link (to a valid cache) is not read.
  fs::create_symlink(path, dir.path() + "/a/b/link.bin");
  EXPECT_FALSE(LimbDatabase::Load(dir.path() + "/a/b/link.bin", 42, &reason));
  EXPECT_NE(reason.find("symbolic link"), std::string::npos) << reason;

  // A cache folder that is a symbolic link is neither read from nor written to.
  fs::create_directory_symlink(dir.path() + "/a/b", dir.path() + "/planted");
  EXPECT_FALSE(LimbDatabase::Load(dir.path() + "/planted/db.bin", 42, &reason));
  EXPECT_NE(reason.find("is a symbolic link"), std::string::npos) << reason;
  EXPECT_THROW(built.Save(dir.path() + "/planted/other.bin", 42), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir.path() + "/a/b/other.bin"));

  // A folder others may write to is not trusted.
  fs::permissions(dir.path() + "/a/b", fs::perms::all);
  EXPECT_FALSE(LimbDatabase::Load(path, 42, &reason));
  EXPECT_NE(reason.find("may be written by other users"), std::string::npos) << reason;
  EXPECT_THROW(built.Save(path, 42), std::runtime_error);
}

TEST(LimbDatabaseCache, AFileLargerThanTheConfigurationWritesIsNotRead) {
  ScratchDir dir;
  const LimbDatabase built = LimbDatabase::Build(Anymal(), SmallConfig(kSamples));
  const std::string path = dir.path() + "/db.bin";
  built.Save(path, 42);
  const std::uint64_t limit = LimbDatabase::MaxCacheBytes(kSamples);
  EXPECT_LE(fs::file_size(path), limit) << "a real cache fits the limit";
  std::string reason;
  ASSERT_TRUE(LimbDatabase::Load(path, 42, &reason, limit)) << reason;
  // Grown (sparse: no disk used) to 4 GB: refused from its size, before anything is read.
  fs::resize_file(path, std::uint64_t{1} << 32);
  EXPECT_FALSE(LimbDatabase::Load(path, 42, &reason, limit));
  EXPECT_NE(reason.find("4294967296 bytes, more than the " + std::to_string(limit)), std::string::npos) << reason;
}

TEST(LimbDatabaseCache, LoadOrBuildBuildsOnceThenLoads) {
  ScratchDir dir;
  const LimbDatabaseConfig config = SmallConfig(kSamples, dir.path());
  LimbDatabaseCacheReport first;
  const LimbDatabase built = LimbDatabase::LoadOrBuild(Anymal(), RobotFiles(), config, &first);
  EXPECT_FALSE(first.loaded);
  EXPECT_NE(first.rebuild_reason.find("no cache file"), std::string::npos) << first.rebuild_reason;
  EXPECT_TRUE(first.write_error.empty()) << first.write_error;
  EXPECT_EQ(first.cache_path, LimbDatabase::CachePath(config, first.key));
  EXPECT_EQ(fs::path(first.cache_path).parent_path(), fs::path(dir.path()));
  EXPECT_TRUE(fs::exists(first.cache_path));

  LimbDatabaseCacheReport second;
  const LimbDatabase loaded = LimbDatabase::LoadOrBuild(Anymal(), RobotFiles(), config, &second);
  EXPECT_TRUE(second.loaded) << second.rebuild_reason;
  EXPECT_TRUE(second.rebuild_reason.empty());
  EXPECT_EQ(second.key, first.key);
  ExpectSameDatabase(built, loaded);
  // The cached database equals a fresh build.
  ExpectSameDatabase(LimbDatabase::Build(Anymal(), config), loaded);
  EXPECT_EQ(FilesIn(dir.path()).size(), 1u);
}

TEST(LimbDatabaseCache, KeyFollowsRobotFileContentAndConfiguration) {
  ScratchDir dir;
  const LimbDatabaseConfig config = SmallConfig(kSamples, dir.path());
  const std::uint64_t key = LimbDatabase::CacheKey(RobotFiles(), config);
  EXPECT_EQ(key, LimbDatabase::CacheKey(RobotFiles(), config));

  // Copies of the robot files give the same key: content, not paths.
  fs::create_directories(dir.path() + "/robots");
  const std::string urdf = dir.path() + "/robots/anymal_b.urdf";
  const std::string yaml = dir.path() + "/robots/anymal_b.yaml";
  fs::copy_file(RobotFiles()[0], urdf);
  fs::copy_file(RobotFiles()[1], yaml);
  EXPECT_EQ(LimbDatabase::CacheKey({urdf, yaml}, config), key);
  EXPECT_EQ(LimbDatabase::DefaultRobotFiles(dir.path()), (std::vector<std::string>{urdf, yaml}));

  // Any change of the yaml content changes the key, even a comment.
  WriteBytes(yaml, ReadBytes(yaml) + "# edited\n");
  const std::uint64_t edited = LimbDatabase::CacheKey({urdf, yaml}, config);
  EXPECT_NE(edited, key);

  // Every configuration value that changes the data changes the key; the cache folder does not.
  auto key_with = [&](auto change) {
    LimbDatabaseConfig c = config;
    change(c);
    return LimbDatabase::CacheKey(RobotFiles(), c);
  };
  EXPECT_NE(key_with([](LimbDatabaseConfig& c) { c.samples_per_leg += 1; }), key);
  EXPECT_NE(key_with([](LimbDatabaseConfig& c) { c.octree_resolution = 0.02; }), key);
  EXPECT_NE(key_with([](LimbDatabaseConfig& c) { c.seed += 1; }), key);
  EXPECT_NE(key_with([](LimbDatabaseConfig& c) { c.weight_haa = 100.0; }), key);
  EXPECT_NE(key_with([](LimbDatabaseConfig& c) { c.weight_hfe = 2.0; }), key);
  EXPECT_NE(key_with([](LimbDatabaseConfig& c) { c.weight_kfe = 0.5; }), key);
  EXPECT_EQ(key_with([](LimbDatabaseConfig& c) { c.cache_dir = "/elsewhere"; }), key);

  EXPECT_THROW(LimbDatabase::CacheKey({dir.path() + "/missing.urdf"}, config), InputError);
}

TEST(LimbDatabaseCache, EditedRobotFileTriggersARebuild) {
  ScratchDir dir;
  const LimbDatabaseConfig config = SmallConfig(kSamples, dir.path() + "/cache");
  fs::create_directories(dir.path() + "/robots");
  const std::vector<std::string> files = LimbDatabase::DefaultRobotFiles(dir.path());
  fs::copy_file(RobotFiles()[0], files[0]);
  fs::copy_file(RobotFiles()[1], files[1]);

  LimbDatabaseCacheReport report;
  LimbDatabase::LoadOrBuild(Anymal(), files, config, &report);
  EXPECT_FALSE(report.loaded);
  LimbDatabase::LoadOrBuild(Anymal(), files, config, &report);
  EXPECT_TRUE(report.loaded);
  const std::string old_path = report.cache_path;

  WriteBytes(files[1], ReadBytes(files[1]) + "# edited\n");
  LimbDatabase::LoadOrBuild(Anymal(), files, config, &report);
  EXPECT_FALSE(report.loaded);
  EXPECT_NE(report.cache_path, old_path);
  LimbDatabase::LoadOrBuild(Anymal(), files, config, &report);
  EXPECT_TRUE(report.loaded);
}

TEST(LimbDatabaseCache, TruncatedOrEmptyFilesAreRejectedAndRebuilt) {
  ScratchDir dir;
  const LimbDatabaseConfig config = SmallConfig(kSamples, dir.path());
  LimbDatabaseCacheReport report;
  const LimbDatabase original = LimbDatabase::LoadOrBuild(Anymal(), RobotFiles(), config, &report);
  const std::string path = report.cache_path;
  const std::string bytes = ReadBytes(path);
  ASSERT_GT(bytes.size(), 1000u);

  for (std::size_t size : {bytes.size() / 2, bytes.size() - 1, std::size_t{60}, std::size_t{20}, std::size_t{0}}) {
    WriteBytes(path, bytes.substr(0, size));
    std::string reason;
    EXPECT_FALSE(LimbDatabase::Load(path, report.key, &reason)) << size;
    EXPECT_NE(reason.find("truncated"), std::string::npos) << reason;

    LimbDatabaseCacheReport again;
    const LimbDatabase rebuilt = LimbDatabase::LoadOrBuild(Anymal(), RobotFiles(), config, &again);
    EXPECT_FALSE(again.loaded) << size;
    EXPECT_FALSE(again.rebuild_reason.empty());
    EXPECT_EQ(ReadBytes(path), bytes) << "the rebuilt cache is written again";
    ExpectSameDatabase(original, rebuilt);
  }
  // Extra bytes at the end are refused too.
  WriteBytes(path, bytes + "x");
  EXPECT_FALSE(LimbDatabase::Load(path, report.key));
}

TEST(LimbDatabaseCache, CorruptedFilesAreRejected) {
  ScratchDir dir;
  const LimbDatabaseConfig config = SmallConfig(kSamples, dir.path());
  LimbDatabaseCacheReport report;
  LimbDatabase::LoadOrBuild(Anymal(), RobotFiles(), config, &report);
  const std::string path = report.cache_path;
  const std::string bytes = ReadBytes(path);
  using namespace limb_database_detail;
  auto rejected_with = [&](std::string corrupted, const std::string& expected_reason) {
    WriteBytes(path, corrupted);
    std::string reason;
    EXPECT_FALSE(LimbDatabase::Load(path, report.key, &reason)) << expected_reason;
    EXPECT_NE(reason.find(expected_reason), std::string::npos) << reason;
    LimbDatabaseCacheReport again;
    LimbDatabase::LoadOrBuild(Anymal(), RobotFiles(), config, &again);
    EXPECT_FALSE(again.loaded);
    EXPECT_TRUE(LimbDatabase::Load(path, report.key)) << "rebuilt cache is valid";
  };

  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x10);
  rejected_with(flipped, "checksum");

  std::string magic = bytes;
  magic[0] = 'X';
  rejected_with(magic, "magic");

  std::string key = bytes;
  key[kCacheKeyOffset] = static_cast<char>(key[kCacheKeyOffset] ^ 1);
  rejected_with(key, "key");

  // Consistent checksums over inconsistent content: the structural checks catch it.
  const std::size_t n = kSamples;
  const std::size_t lf = kCacheHeaderBytes + kCachePayloadPreambleBytes + kCacheLegHeaderBytes;
  std::string bad_score = bytes;
  const double two = 2.0;
  std::memcpy(bad_score.data() + lf + 6 * n * sizeof(double), &two, sizeof(two));
  FixChecksum(&bad_score);
  rejected_with(bad_score, "score");

  std::string moved_foot = bytes;
  double x = 0.0;
  std::memcpy(&x, moved_foot.data() + lf + 3 * n * sizeof(double), sizeof(x));
  x += 0.5;
  std::memcpy(moved_foot.data() + lf + 3 * n * sizeof(double), &x, sizeof(x));
  FixChecksum(&moved_foot);
  rejected_with(moved_foot, "does not lie in");

  std::string huge_count = bytes;
  const std::uint64_t huge = 1ull << 40;
  std::memcpy(huge_count.data() + kCacheHeaderBytes + kCachePayloadPreambleBytes, &huge, sizeof(huge));
  FixChecksum(&huge_count);
  rejected_with(huge_count, "count");

  std::string nan_joint = bytes;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(nan_joint.data() + lf, &nan, sizeof(nan));
  FixChecksum(&nan_joint);
  rejected_with(nan_joint, "non-finite");
}

TEST(LimbDatabaseCache, UnwritableCacheFolderIsReportedNotThrown) {
  ScratchDir dir;
  WriteBytes(dir.path() + "/plain_file", "not a folder");
  const LimbDatabaseConfig config = SmallConfig(kSamples, dir.path() + "/plain_file/cache");
  LimbDatabaseCacheReport report;
  const LimbDatabase db = LimbDatabase::LoadOrBuild(Anymal(), RobotFiles(), config, &report);
  EXPECT_FALSE(report.loaded);
  EXPECT_FALSE(report.write_error.empty());
  EXPECT_EQ(db.NumSamples(Leg::kRH), kSamples);
}

TEST(LimbDatabaseCache, MissingRobotFileIsAnInputError) {
  ScratchDir dir;
  EXPECT_THROW(
      LimbDatabase::LoadOrBuild(Anymal(), {dir.path() + "/none.urdf"}, SmallConfig(kSamples, dir.path())),
      InputError);
}

}  // namespace
}  // namespace rbcp
