// Limb database cache: key, binary file writer and validating reader, LoadOrBuild. The file
// layout is described in cache_format.h.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>

#include "cache_format.h"
#include "limb_database_impl.h"
#include "rbcp/core/error.h"
#include "rbcp/limb_database/limb_database.h"

namespace rbcp {
namespace limb_database_detail {

std::uint64_t Hash64(const char* data, std::size_t size) {
  constexpr std::uint64_t kMul = 0x9E3779B97F4A7C15ull;
  std::uint64_t h = 0xcbf29ce484222325ull ^ size;
  auto mix = [&](std::uint64_t w) {
    h ^= w;
    h *= kMul;
    h ^= h >> 32;
  };
  std::size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, data + i, 8);
    mix(w);
  }
  if (i < size) {
    std::uint64_t w = 0;
    std::memcpy(&w, data + i, size - i);
    mix(w);
  }
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 32;
  return h;
}

}  // namespace limb_database_detail

namespace {

using limb_database_detail::CellRecord;
using limb_database_detail::Hash64;
using limb_database_detail::LegData;

constexpr const char (&kMagic)[8] = limb_database_detail::kCacheMagic;
constexpr std::uint32_t kFormatVersion = limb_database_detail::kCacheFormatVersion;
constexpr std::size_t kHeaderBytes = limb_database_detail::kCacheHeaderBytes;
/// Part of the cache key: changes whenever the generation (sampler, self-collision filter, score,
/// ordering) changes, so that caches written by an older generation are rebuilt.
constexpr std::uint32_t kGenerationVersion = 1;

template <typename T>
void Put(std::string* out, const T& v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
void PutArray(std::string* out, const std::vector<T>& v) {
  out->append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

/// Bounds-checked sequential reader over a byte buffer.
class Reader {
 public:
  Reader(const char* data, std::size_t size) : p_(data), left_(size) {}
  template <typename T>
  bool Get(T* v) {
    if (left_ < sizeof(T)) return false;
    std::memcpy(v, p_, sizeof(T));
    p_ += sizeof(T);
    left_ -= sizeof(T);
    return true;
  }
  template <typename T>
  bool GetArray(std::vector<T>* v, std::uint64_t count) {
    if (count > left_ / sizeof(T)) return false;
    v->resize(static_cast<std::size_t>(count));
    std::memcpy(v->data(), p_, static_cast<std::size_t>(count) * sizeof(T));
    p_ += count * sizeof(T);
    left_ -= static_cast<std::size_t>(count) * sizeof(T);
    return true;
  }
  std::size_t Left() const { return left_; }

 private:
  const char* p_;
  std::size_t left_;
};

std::string ReadWholeFile(const std::string& path, bool* ok) {
  *ok = false;
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return {};
  const std::streamoff size = in.tellg();
  if (size < 0) return {};
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), size)) return {};
  *ok = true;
  return bytes;
}

/// Creates `dir` and its missing parents owner-only (0700) when `create`. nullopt when `dir` is
/// then a real folder (no symbolic link) of this user that no other user may write to; else why not.
std::optional<std::string> PrivateFolderProblem(const std::filesystem::path& dir, bool create) {
  if (create) {
    std::filesystem::path partial;
    for (const auto& part : dir) {
      partial /= part;
      if (::mkdir(partial.c_str(), 0700) != 0 && errno != EEXIST) {
        return partial.string() + ": cannot create the folder: " + std::strerror(errno);
      }
    }
  }
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0) return dir.string() + ": " + std::strerror(errno);
  if (S_ISLNK(st.st_mode)) return dir.string() + " is a symbolic link";
  if (!S_ISDIR(st.st_mode)) return dir.string() + " is not a folder";
  if (st.st_uid != ::geteuid()) return dir.string() + " belongs to another user";
  if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) return dir.string() + " may be written by other users";
  return std::nullopt;
}

/// Reads the file at `path` (a regular file of this user, no symbolic link, at most `max_bytes`
/// when > 0, checked before reading). Returns nullopt and fills *bytes, or why not.
std::optional<std::string> ReadCacheFile(const std::string& path, std::uint64_t max_bytes, std::string* bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    if (errno == ENOENT) return std::string("no cache file");
    if (errno == ELOOP) return std::string("a symbolic link, not read");
    return std::string("unreadable: ") + std::strerror(errno);
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) return std::string("unreadable: ") + std::strerror(errno);
  if (!S_ISREG(st.st_mode)) return std::string("not a regular file");
  if (st.st_uid != ::geteuid()) return std::string("belongs to another user, not read");
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (max_bytes > 0 && size > max_bytes) {
    return std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
           " a cache of this configuration takes; not read";
  }
  bytes->assign(static_cast<std::size_t>(size), '\0');
  std::size_t done = 0;
  while (done < bytes->size()) {
    const ssize_t n = ::read(fd, bytes->data() + done, bytes->size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return std::string("unreadable (shorter than its size)");
    done += static_cast<std::size_t>(n);
  }
  return std::nullopt;
}

bool AllFinite(const std::vector<double>& v) {
  for (double x : v) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

/// Structural checks of one leg read from a file: nullopt when consistent, else what is not.
std::optional<std::string> CheckLeg(const LegData& d, double resolution) {
  const std::size_t n = d.score.size();
  if (n == 0) return std::string("a leg without samples");
  if (!AllFinite(d.q) || !AllFinite(d.foot)) return std::string("non-finite joint values or foot positions");
  for (double s : d.score) {
    if (!(s >= 0.0 && s <= 1.0)) return std::string("a score outside [0, 1]");
  }
  if (d.draws < static_cast<std::int64_t>(n) - 1) return std::string("fewer draws than samples");
  limb_database_detail::CellTree keyer(resolution);
  std::uint64_t next = 0;
  for (std::size_t c = 0; c < d.cells.size(); ++c) {
    const CellRecord& cell = d.cells[c];
    if (cell.first_sample != next || cell.num_samples == 0 || cell.num_samples > n - next) {
      return std::string("cell slices that do not tile the samples");
    }
    if (c > 0 && !(d.cells[c - 1].key < cell.key)) return std::string("cells out of key order");
    for (std::uint32_t k = cell.first_sample; k < cell.first_sample + cell.num_samples; ++k) {
      octomap::OcTreeKey key;
      const Eigen::Vector3d p = d.Foot(k);
      if (!keyer.coordToKeyChecked(p.x(), p.y(), p.z(), key) || key[0] != cell.key[0] || key[1] != cell.key[1] ||
          key[2] != cell.key[2]) {
        return std::string("a sample stored in a cell its foot does not lie in");
      }
    }
    next += cell.num_samples;
  }
  if (next != n) return std::string("cell slices that do not tile the samples");
  return std::nullopt;
}

std::string Hex(std::uint64_t v) {
  std::ostringstream os;
  os << std::hex << std::setw(16) << std::setfill('0') << v;
  return os.str();
}

}  // namespace

std::vector<std::string> LimbDatabase::DefaultRobotFiles(const std::string& config_dir) {
  return {config_dir + "/robots/anymal_b.urdf", config_dir + "/robots/anymal_b.yaml"};
}

std::uint64_t LimbDatabase::CacheKey(const std::vector<std::string>& robot_files, const LimbDatabaseConfig& config) {
  std::string material = "rbcp limb database";
  Put(&material, kFormatVersion);
  Put(&material, kGenerationVersion);
  Put(&material, static_cast<std::uint64_t>(robot_files.size()));
  for (const std::string& path : robot_files) {
    bool ok = false;
    const std::string content = ReadWholeFile(path, &ok);
    if (!ok) throw InputError(path + ": cannot read the robot file for the limb database cache key");
    Put(&material, static_cast<std::uint64_t>(content.size()));
    material += content;
  }
  Put(&material, static_cast<std::int64_t>(config.samples_per_leg));
  Put(&material, config.octree_resolution);
  Put(&material, static_cast<std::uint64_t>(config.seed));
  Put(&material, config.weight_haa);
  Put(&material, config.weight_hfe);
  Put(&material, config.weight_kfe);
  return Hash64(material.data(), material.size());
}

std::string LimbDatabase::CachePath(const LimbDatabaseConfig& config, std::uint64_t key) {
  const std::string dir = config.ResolvedCacheDir();
  if (dir.empty()) return "";
  return (std::filesystem::path(dir) / ("limb_db_" + Hex(key) + ".bin")).string();
}

std::uint64_t LimbDatabase::MaxCacheBytes(int samples_per_leg) {
  const auto n = static_cast<std::uint64_t>(std::max(samples_per_leg, 0));
  const std::uint64_t per_sample = 7 * sizeof(double) + sizeof(CellRecord);  // q, foot, score; a cell at most
  const std::uint64_t per_leg = 2 * sizeof(std::uint64_t) + sizeof(LegData::draws) + n * per_sample;
  return kHeaderBytes + sizeof(double) + kNumLegs * per_leg;
}

void LimbDatabase::Save(const std::string& path, std::uint64_t key) const {
  std::string payload;
  Put(&payload, impl_->resolution);
  for (const LegData& d : impl_->legs) {
    Put(&payload, static_cast<std::uint64_t>(d.score.size()));
    Put(&payload, static_cast<std::uint64_t>(d.cells.size()));
    Put(&payload, d.draws);
    PutArray(&payload, d.q);
    PutArray(&payload, d.foot);
    PutArray(&payload, d.score);
    PutArray(&payload, d.cells);
  }
  std::string header;
  header.append(kMagic, sizeof(kMagic));
  Put(&header, kFormatVersion);
  Put(&header, static_cast<std::uint32_t>(kHeaderBytes));
  Put(&header, key);
  Put(&header, static_cast<std::uint64_t>(payload.size()));
  Put(&header, Hash64(payload.data(), payload.size()));
  Put(&header, std::uint64_t{0});
  RBCP_CHECK(header.size() == kHeaderBytes, "cache header size");

  const std::filesystem::path target(path);
  std::error_code ec;
  if (auto unsafe = PrivateFolderProblem(target.has_parent_path() ? target.parent_path() : ".", true)) {
    throw std::runtime_error(path + ": no private cache folder: " + *unsafe);
  }
  static std::atomic<unsigned> counter{0};
  const std::string temp =
      path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  {
    // A new file of this user only: an existing file or link of that name is not written through.
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0) throw std::runtime_error(temp + ": cannot create the limb database cache: " + std::strerror(errno));
    bool written = true;
    for (const std::string* part : {&header, &payload}) {
      std::size_t done = 0;
      while (written && done < part->size()) {
        const ssize_t n = ::write(fd, part->data() + done, part->size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) written = false;
        else done += static_cast<std::size_t>(n);
      }
    }
    if (::close(fd) != 0) written = false;
    if (!written) {
      std::filesystem::remove(temp, ec);
      throw std::runtime_error(temp + ": cannot write the limb database cache");
    }
  }
  std::filesystem::rename(temp, target, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw std::runtime_error(path + ": cannot move the limb database cache into place: " + ec.message());
  }
}

std::optional<LimbDatabase> LimbDatabase::Load(const std::string& path, std::uint64_t expected_key,
                                               std::string* reason, std::uint64_t max_bytes) {
  auto fail = [&](const std::string& why) -> std::optional<LimbDatabase> {
    if (reason) *reason = path + ": " + why;
    return std::nullopt;
  };
  std::string bytes;
  if (auto unreadable = ReadCacheFile(path, max_bytes, &bytes)) return fail(*unreadable);
  // A file in a folder others can write to may have been planted there.
  const std::filesystem::path file(path);
  if (auto unsafe = PrivateFolderProblem(file.has_parent_path() ? file.parent_path() : ".", false)) {
    return fail("the cache folder is not private: " + *unsafe);
  }
  if (bytes.size() < kHeaderBytes) return fail("truncated header (" + std::to_string(bytes.size()) + " bytes)");
  if (std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) return fail("not a limb database cache (bad magic)");
  Reader header(bytes.data() + sizeof(kMagic), kHeaderBytes - sizeof(kMagic));
  std::uint32_t version = 0, header_bytes = 0;
  std::uint64_t key = 0, payload_bytes = 0, checksum = 0;
  header.Get(&version);
  header.Get(&header_bytes);
  header.Get(&key);
  header.Get(&payload_bytes);
  header.Get(&checksum);
  if (version != kFormatVersion || header_bytes != kHeaderBytes) {
    return fail("format version " + std::to_string(version) + ", expected " + std::to_string(kFormatVersion));
  }
  if (key != expected_key) return fail("written for key " + Hex(key) + ", expected " + Hex(expected_key));
  if (payload_bytes != bytes.size() - kHeaderBytes) {
    return fail("payload of " + std::to_string(bytes.size() - kHeaderBytes) + " bytes, expected " +
                std::to_string(payload_bytes) + " (truncated or extended)");
  }
  const char* payload = bytes.data() + kHeaderBytes;
  if (Hash64(payload, static_cast<std::size_t>(payload_bytes)) != checksum) return fail("checksum mismatch");

  auto impl = std::make_unique<Impl>();
  Reader in(payload, static_cast<std::size_t>(payload_bytes));
  if (!in.Get(&impl->resolution) || !(impl->resolution >= 0.001 && impl->resolution <= 0.5)) {
    return fail("invalid octree resolution");
  }
  for (Leg leg : kAllLegs) {
    LegData& d = impl->legs[static_cast<std::size_t>(Index(leg))];
    std::uint64_t n = 0, cells = 0;
    if (!in.Get(&n) || !in.Get(&cells) || !in.Get(&d.draws)) return fail("truncated leg header");
    if (n == 0 || n > 10'000'000 || cells == 0 || cells > n) return fail("invalid sample or cell count");
    if (!in.GetArray(&d.q, 3 * n) || !in.GetArray(&d.foot, 3 * n) || !in.GetArray(&d.score, n) ||
        !in.GetArray(&d.cells, cells)) {
      return fail("truncated sample arrays");
    }
    if (auto problem = CheckLeg(d, impl->resolution)) return fail("leg " + std::string(LegName(leg)) + ": " + *problem);
    d.Index(impl->resolution);
  }
  if (in.Left() != 0) return fail("trailing bytes after the last leg");
  if (reason) reason->clear();
  return LimbDatabase(std::move(impl));
}

LimbDatabase LimbDatabase::LoadOrBuild(const RobotModel& model, const std::vector<std::string>& robot_files,
                                       const LimbDatabaseConfig& config, LimbDatabaseCacheReport* report) {
  config.Validate();
  LimbDatabaseCacheReport local;
  LimbDatabaseCacheReport& r = report ? *report : local;
  r = LimbDatabaseCacheReport();
  r.key = CacheKey(robot_files, config);
  r.cache_path = CachePath(config, r.key);
  if (r.cache_path.empty()) {
    r.rebuild_reason = r.write_error =
        "no cache folder: XDG_CACHE_HOME and HOME are unset and the user has no home folder";
    return Build(model, config);
  }
  std::string reason;
  std::optional<LimbDatabase> cached = Load(r.cache_path, r.key, &reason, MaxCacheBytes(config.samples_per_leg));
  if (cached && cached->Resolution() == config.octree_resolution && cached->NumSamples(Leg::kLF) == config.samples_per_leg) {
    r.loaded = true;
    return std::move(*cached);
  }
  r.rebuild_reason = cached ? r.cache_path + ": contents do not match the configuration" : reason;
  LimbDatabase db = Build(model, config);
  try {
    db.Save(r.cache_path, r.key);
  } catch (const std::exception& e) {
    r.write_error = e.what();
  }
  return db;
}

}  // namespace rbcp
