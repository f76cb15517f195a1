#pragma once
/// Limb database (RB-PRM): per leg, a large set of collision-free joint configurations indexed by
/// foot position in an octree, each with an offline score. The contact planner asks it which
/// configurations put the foot on (or within a tolerance of) a contact surface.
///
/// Contents, per leg:
///  * sample 0 of the generation is the reference standing configuration; the others are drawn
///    uniformly within the planning joint bounds from a generator seeded by (seed, leg). Draws in
///    self-collision are rejected (shank, adapter tube and foot against the trunk primitives and
///    the leg's own hip; thigh against the trunk; the other legs are not tested), until
///    `samples_per_leg` configurations are collected;
///  * the foot contact point of each sample in the base frame (RobotModel::FootPosition);
///  * the offline score: 100 - sqrt(w_HAA dq_HAA^2 + w_HFE dq_HFE^2 + w_KFE dq_KFE^2) with dq the
///    offset from the reference configuration, min-max normalised over the leg's samples to
///    [0, 1] (1 = the reference configuration, the closest possible).
/// Samples are indexed by foot position in an octree of `octree_resolution` cells: each occupied
/// leaf cell owns a contiguous slice of the sample arrays, sorted by score (descending, ties by
/// generation order). Cells are ordered by their octree key (x, then y, then z).
///
/// Frames and units: base frame (x forward, y left, z up) for sample foot positions; world frame
/// for surfaces and candidates; [m], [rad].
///
/// Caching: LoadOrBuild() keys a binary cache file by a hash of the robot files' content and of
/// every configuration value that changes the data. A missing, stale, truncated or corrupted file
/// is detected (magic, format version, key, size, checksum, structural checks) and rebuilt; the
/// new file is written atomically (temporary file, then rename). The cache is native-endian and
/// meant for the machine that wrote it.
///
/// Every query is const and safe to call from several threads at once.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/leg.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {

/// Parameters of the limb database (config/limb_database.yaml).
struct LimbDatabaseConfig {
  int samples_per_leg = 50000;
  double octree_resolution = 0.01;
  unsigned seed = 1;
  double weight_haa = 1.0;
  double weight_hfe = 1.0;
  double weight_kfe = 1.0;
  /// Empty: $XDG_CACHE_HOME/rbcp/limb_database (an absolute XDG_CACHE_HOME), else
  /// $HOME/.cache/rbcp/limb_database, else the same below the user's home folder in the password
  /// database, else no cache. A relative path is taken from the working directory. The folder is
  /// created owner-only (0700) and used only when it is a real folder (no symbolic link) of the
  /// user that no one else may write to. Not part of the cache key.
  std::string cache_dir;

  template <class Visitor>
  void Serialize(Visitor* v) {
    // Sample indices are stored as 32-bit integers; ten million per leg is far beyond any use.
    v->Visit("samples_per_leg", &samples_per_leg, "", bounds::Closed(1, 10'000'000),
             "configurations per leg, the reference configuration included");
    // The octree spans 65536 cells per axis around the base; 1 mm cells still cover +-32 m.
    v->Visit("octree_resolution", &octree_resolution, "m", bounds::Closed(0.001, 0.5), "edge of an octree leaf cell");
    v->Visit("seed", &seed, "", bounds::NonNegative(), "sampler seed; leg l draws from a generator seeded by (seed, l)");
    v->Visit("weight_haa", &weight_haa, "1/rad^2", bounds::NonNegative(),
             "offline score: 100 - sqrt(sum_j w_j (q_j - q_ref_j)^2), min-max normalised per leg to [0, 1]; the "
             "weight of HAA");
    v->Visit("weight_hfe", &weight_hfe, "1/rad^2", bounds::NonNegative(), "the weight of HFE");
    v->Visit("weight_kfe", &weight_kfe, "1/rad^2", bounds::NonNegative(), "the weight of KFE");
    v->Rule("weight_haa + weight_hfe + weight_kfe", weight_haa + weight_hfe + weight_kfe > 0.0, "a positive sum",
            ConfigNumber(weight_haa + weight_hfe + weight_kfe));
    v->Visit("cache_dir", &cache_dir,
             "folder of the cache files, keyed by the content of the robot files and the values above (\"\": the "
             "user's cache folder, see LimbDatabaseConfig::cache_dir)");
  }

  /// Reads every key strictly (missing or unknown keys, wrong types and out-of-range values throw
  /// InputError naming the key).
  static LimbDatabaseConfig Load(const YamlMap& map) { return LoadConfig<LimbDatabaseConfig>(map); }
  static LimbDatabaseConfig LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
  /// Throws InputError describing the first out-of-range value.
  void Validate(const std::string& where = "LimbDatabaseConfig") const { ValidateConfig(*this, where); }
  /// The folder cache files go to (cache_dir, or the default described above); "" for none.
  std::string ResolvedCacheDir() const;
};

/// One configuration of a leg.
struct LimbSample {
  Eigen::Vector3d q = Eigen::Vector3d::Zero();       ///< (HAA, HFE, KFE) [rad]
  Eigen::Vector3d foot_B = Eigen::Vector3d::Zero();  ///< foot contact point, base frame [m]
  double score = 0.0;                                ///< offline score in [0, 1], 1 = reference
};

/// One occupied octree leaf cell: the samples first_sample .. first_sample + num_samples - 1.
struct LimbCell {
  Eigen::Vector3d centre_B = Eigen::Vector3d::Zero();  ///< cell centre, base frame [m]
  int first_sample = 0;
  int num_samples = 0;
};

/// A convex planar contact surface, world frame.
struct ConvexSurface {
  /// Convex polygon vertices [m], in order around the boundary (either direction), >= 3.
  std::vector<Eigen::Vector3d> vertices;
  /// Plane normal (normalised by the query).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

/// A database sample whose foot lies within the query's distance of a surface.
struct FootholdCandidate {
  Leg leg = Leg::kLF;
  int sample = -1;            ///< index into the leg's samples (LimbDatabase::Sample)
  int surface = -1;           ///< the caller's surface index passed to the query
  double static_score = 0.0;  ///< the sample's offline score [0, 1]
  double distance = 0.0;      ///< distance from the foot to the surface polygon [m]
  Eigen::Vector3d foot_W = Eigen::Vector3d::Zero();     ///< sample foot at the query base pose [m]
  Eigen::Vector3d closest_W = Eigen::Vector3d::Zero();  ///< closest point of the polygon [m]
};

/// What LoadOrBuild() did.
struct LimbDatabaseCacheReport {
  std::uint64_t key = 0;       ///< cache key of the robot files and configuration
  std::string cache_path;      ///< file read or written
  bool loaded = false;         ///< true when the database came from the cache file
  std::string rebuild_reason;  ///< why the database was built (empty when loaded)
  std::string write_error;     ///< why the cache file could not be written (empty otherwise)
};

class LimbDatabase {
 public:
  /// Samples and indexes the four legs. Throws InputError for an invalid configuration, a
  /// reference configuration in self-collision or joint bounds that leave (almost) no
  /// collision-free configuration.
  static LimbDatabase Build(const RobotModel& model, const LimbDatabaseConfig& config);

  /// Loads the cache file of (robot files, config) from config.ResolvedCacheDir() when it is
  /// valid, otherwise builds the database and writes the cache file. `robot_files` are the files
  /// the model was loaded from (URDF and YAML); their content is part of the key. A cache that
  /// cannot be written is reported, not thrown. Throws InputError when a robot file is unreadable.
  static LimbDatabase LoadOrBuild(const RobotModel& model, const std::vector<std::string>& robot_files,
                                  const LimbDatabaseConfig& config, LimbDatabaseCacheReport* report = nullptr);
  /// config_dir/robots/anymal_b.urdf and .yaml, the files of RobotModel::LoadDefault(config_dir).
  static std::vector<std::string> DefaultRobotFiles(const std::string& config_dir);

  /// Hash of the robot files' content, the configuration values that change the database
  /// (samples_per_leg, octree_resolution, seed, weights) and the generation and file format
  /// versions. Throws InputError when a file is unreadable.
  static std::uint64_t CacheKey(const std::vector<std::string>& robot_files, const LimbDatabaseConfig& config);
  /// The cache file of a key: <config.ResolvedCacheDir()>/limb_db_<16 hex digits>.bin; "" when
  /// there is no cache folder.
  static std::string CachePath(const LimbDatabaseConfig& config, std::uint64_t key);

  /// Writes the database to `path` under `key`, atomically (a new owner-only temporary file in
  /// the same folder, then rename); creates the folder owner-only (0700). Throws
  /// std::runtime_error on an I/O failure or when the folder is not private (a symbolic link,
  /// another user's, or writable by others).
  void Save(const std::string& path, std::uint64_t key) const;
  /// Reads a file written by Save(). Returns nullopt and sets *reason when the folder is not
  /// private, or the file is missing, a symbolic link, another user's, larger than `max_bytes`
  /// (checked before reading; 0: no limit), unreadable, written under another key or format,
  /// truncated, corrupted or inconsistent.
  static std::optional<LimbDatabase> Load(const std::string& path, std::uint64_t expected_key,
                                          std::string* reason = nullptr, std::uint64_t max_bytes = 0);
  /// The size of the cache file of a database of `samples_per_leg` samples per leg, at most.
  static std::uint64_t MaxCacheBytes(int samples_per_leg);

  LimbDatabase(LimbDatabase&&) noexcept;
  LimbDatabase& operator=(LimbDatabase&&) noexcept;
  LimbDatabase(const LimbDatabase&) = delete;
  LimbDatabase& operator=(const LimbDatabase&) = delete;
  ~LimbDatabase();

  // ---- Samples ---------------------------------------------------------------------------------

  int NumSamples(Leg leg) const;
  /// Sample i of the leg, 0 <= i < NumSamples(leg). Throws InputError when out of range.
  LimbSample Sample(Leg leg, int i) const;
  /// Random configurations drawn for the leg (the reference configuration is not drawn); the
  /// difference to NumSamples(leg) - 1 is the number rejected for self-collision.
  std::int64_t Draws(Leg leg) const;
  /// Octree leaf edge [m].
  double Resolution() const;

  // ---- Cells -----------------------------------------------------------------------------------

  int NumCells(Leg leg) const;
  /// Cell i of the leg, 0 <= i < NumCells(leg). Throws InputError when out of range.
  LimbCell Cell(Leg leg, int i) const;
  /// Index of the cell containing the base-frame point p_B [m], or -1 when no sample lies in it.
  int CellIndexAt(Leg leg, const Eigen::Vector3d& p_B) const;

  // ---- Queries ---------------------------------------------------------------------------------

  /// Every sample of the leg whose foot lies within max_distance [m] of the surface polygon
  /// when the base is at base_pose_W. All of them: no cap. Cells are visited in key order (x,
  /// then y, then z; per key column only the z range the polygon's plane slab can reach) and the
  /// samples of a cell by descending score; callers rank them with their own heuristic.
  /// A polygon without area (collinear or repeated vertices, e.g. a surface clipped to a sliver)
  /// gives no candidates. Throws InputError for fewer than 3 vertices, non-finite vertices, a
  /// zero or non-finite normal, or a negative or non-finite max_distance.
  std::vector<FootholdCandidate> Candidates(Leg leg, const Eigen::Isometry3d& base_pose_W,
                                            const ConvexSurface& surface, double max_distance) const;
  /// As Candidates(), appending to *out and tagging the candidates with surface_index, so the
  /// candidates of several surfaces can be merged without copies.
  void AppendCandidates(Leg leg, const Eigen::Isometry3d& base_pose_W, const std::vector<Eigen::Vector3d>& vertices_W,
                        const Eigen::Vector3d& normal_W, double max_distance, int surface_index,
                        std::vector<FootholdCandidate>* out) const;
  /// As AppendCandidates(), handing each candidate to `visit` instead of storing it (a caller
  /// that keeps only a few of many candidates saves the copies), in the same order.
  void VisitCandidates(Leg leg, const Eigen::Isometry3d& base_pose_W, const std::vector<Eigen::Vector3d>& vertices_W,
                       const Eigen::Vector3d& normal_W, double max_distance, int surface_index,
                       const std::function<void(const FootholdCandidate&)>& visit) const;
  /// Indices of the samples whose foot lies in the base-frame box [min_B, max_B] (inclusive).
  std::vector<int> SamplesInBox(Leg leg, const Eigen::Vector3d& min_B, const Eigen::Vector3d& max_B) const;

  /// Heap memory held by the sample arrays, cell tables and octrees [bytes] (allocator overhead
  /// not included).
  std::size_t MemoryBytes() const;

 private:
  struct Impl;
  explicit LimbDatabase(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbcp
