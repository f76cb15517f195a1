#pragma once
/// The terrain the robot knows from its depth sensors: a 2.5D elevation map (height and its
/// variance per cell, fused over time) in a square window around the robot, beside a
/// probabilistic 3D occupancy map (OctoMap) of the same window that clears what rays pass through.
/// Free of LCM: the terrain_mapper process feeds it clouds placed in the world frame.
///
/// Conventions: world frame, z up, metres. A cell (ix, iy) covers
/// [origin.x + ix r, origin.x + (ix + 1) r) x [origin.y + iy r, origin.y + (iy + 1) r), r the
/// resolution; the window's origin stays on multiples of r, so a cell keeps its place in the world
/// when the window moves. Unknown cells are no terrain: they are never in the mesh.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/core/yaml_reader.h"

namespace rbcp::mapping {

/// config/mapper.yaml `elevation:`.
struct ElevationMapConfig {
  double resolution_m = 0.04;        ///< side of a cell
  double window_m = 8.0;             ///< side of the square window around the robot
  double recenter_distance_m = 0.5;  ///< the window moves (in whole cells) when the robot is this far from its centre
  double min_variance_m2 = 1e-6;     ///< a cell's variance never falls below this (no estimate is exact)
  double gate_sigma = 3.0;           ///< a point this many standard deviations off a cell's height is not fused (see ElevationMap::Fuse)
  double mesh_smoothing_step_m = 0.02;  ///< ToMesh: a cell's height is averaged with its neighbours within this of it
  double plane_step_m = 0.015;          ///< ToMesh: a plane's cells step at most this from cell to cell and off its plane
  double plane_max_rms_m = 0.01;        ///< ToMesh: a region this close to its least-squares plane (RMS) is that plane
  int plane_min_cells = 9;              ///< ToMesh: regions of fewer cells are not made planes
  int mesh_fill_neighbours = 4;         ///< ToMesh: an unknown cell with this many neighbours on one plane is on it

  template <class Visitor>
  void Serialize(Visitor* v);
};

/// config/mapper.yaml `occupancy:`.
struct OccupancyConfig {
  double resolution_m = 0.05;   ///< side of the octree's smallest voxel
  double max_range_m = 4.0;     ///< rays are integrated up to this far from the sensor
  double clear_probability = 0.3;  ///< a cell whose height lies in a voxel at most this likely occupied is forgotten
  double obstacle_rise_m = 0.25;   ///< TerrainMap::ToMesh: an occupied voxel this far above a cell is an obstacle standing there
  double unseen_top_m = 1.0;       ///< TerrainMap::ToMesh: an obstacle with nothing known above it is meshed this much higher

  template <class Visitor>
  void Serialize(Visitor* v);
};

/// config/mapper.yaml: the terrain mapper (library and process).
struct MapperConfig {
  ElevationMapConfig elevation;
  OccupancyConfig occupancy;
  double publish_period_s = 0.5;     ///< TERRAIN and ELEVATION_MAP go out this often, of the clouds' (simulated) time
  int max_points_per_cloud = 100000; ///< a larger cloud is rejected whole
  double foot_patch_radius_m = 0.03; ///< a stance foot's sole marks the cells within this radius of its contact point

  template <class Visitor>
  void Serialize(Visitor* v);

  static MapperConfig Load(const YamlMap& map);
  static MapperConfig LoadFile(const std::string& path);
  void Validate(const std::string& where = "MapperConfig") const;
};

/// One capture placed in the world frame.
struct WorldCloud {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< [m] the sensor's origin at capture
  std::vector<Eigen::Vector3d> points;               ///< [m] returns, world frame
  double range_noise_std = 0.0;                      ///< [m] 1-sigma range noise along each ray
};

/// What one cloud did to the map.
struct IntegrateReport {
  std::size_t points_fused = 0;     ///< fused into a cell's height
  std::size_t points_gated = 0;     ///< off a cell's height by more than the gate (a lower return seen past an edge)
  std::size_t points_outside = 0;   ///< outside the window or beyond max_range_m
  std::size_t points_invalid = 0;   ///< not finite: skipped
  std::size_t cells_cleared = 0;    ///< known cells forgotten because rays passed through their height
};

struct Cell {
  double height = 0.0;    ///< [m] world z of the terrain's top
  double variance = 0.0;  ///< [m^2]
};

/// The 2.5D grid: per cell, a height estimate and its variance, fused by a one-dimensional
/// Kalman update per point.
class ElevationMap {
 public:
  explicit ElevationMap(const ElevationMapConfig& config);

  /// Moves the window so that `xy` is within recenter_distance_m of its centre (by whole cells;
  /// cells that leave the window are forgotten). The first call places the window.
  void Recenter(const Eigen::Vector2d& xy);
  /// Fuses one measurement of the terrain's height at p.xy (p.z, with `variance`). A measurement
  /// more than gate_sigma standard deviations above the cell's height replaces it (something new
  /// stands there, or the top of a block next to its side); one as far below is not fused (a
  /// return seen past an edge). Where two surfaces share a cell (a block's edge crosses it), the
  /// one measured nearer the cell's centre wins: a measurement off by more than the gate replaces
  /// the height only when it lies nearer the centre than the measurements behind the estimate
  /// (their "support" distance, which grows with every such measurement turned away, so that a
  /// surface that really changed takes over within a few measurements). Returns false when p is
  /// outside the window or gated.
  bool Fuse(const Eigen::Vector3d& p, double variance);
  /// What Fuse did with one measurement.
  enum class FuseOutcome { kOutside, kGated, kFused, kReplaced };
  /// Fuse into cell (ix, iy) a measurement taken `offset_m` from the cell's centre (horizontally);
  /// with `gate` false a measurement off by more than the gate always replaces the height (a foot
  /// standing there is proof of the terrain).
  FuseOutcome FuseCell(int ix, int iy, double z, double variance, double offset_m, bool gate = true);
  /// Forgets one cell.
  void Clear(int ix, int iy);

  std::optional<Cell> At(const Eigen::Vector2d& xy) const;
  std::optional<Cell> At(int ix, int iy) const;
  /// The cell holding xy; nullopt outside the window.
  std::optional<std::pair<int, int>> Index(const Eigen::Vector2d& xy) const;
  Eigen::Vector2d CellCentre(int ix, int iy) const;

  /// Whether Recenter placed the window (before, every cell is outside it).
  bool placed() const { return placed_; }
  Eigen::Vector2d origin() const { return origin_; }
  double resolution() const { return config_.resolution_m; }
  int num_x() const { return n_; }
  int num_y() const { return n_; }
  std::size_t KnownCells() const { return known_; }
  std::size_t MemoryBytes() const;

  /// The known cells as a height field: one vertex per known cell at its centre and height, two
  /// triangles per 2 x 2 block of known cells (one where three of the four are known), so that
  /// neighbouring cells of the same surface share their edges. Counter-clockwise from above. The
  /// heights are smoothed without blurring steps (mesh_smoothing_step_m), a hole of one cell
  /// between the returns of one surface is filled (mesh_fill_neighbours), and a region that is a
  /// plane within the noise (plane_step_m, plane_max_rms_m, plane_min_cells) is meshed exactly on
  /// its least-squares plane: the planners look for planar regions, which the noise of single
  /// returns would break into pieces.
  TriangleMesh ToMesh() const { return MeshOf(MeshHeights()); }
  /// The heights ToMesh meshes, per cell (NaN: not in the mesh).
  std::vector<float> MeshHeights() const;
  /// The mesh of `heights` (one per cell, as MeshHeights gives them; NaN: not in the mesh).
  TriangleMesh MeshOf(const std::vector<float>& heights) const;

 private:
  std::size_t Flat(int ix, int iy) const { return static_cast<std::size_t>(iy) * static_cast<std::size_t>(n_) + static_cast<std::size_t>(ix); }

  ElevationMapConfig config_;
  int n_ = 0;
  bool placed_ = false;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  std::int64_t origin_ix_ = 0;  ///< origin_ in cells (origin_ = origin_i * r), so that it never drifts
  std::int64_t origin_iy_ = 0;
  std::vector<float> height_;    ///< NaN: unknown
  std::vector<float> variance_;
  std::vector<float> support_;   ///< [m] nearest distance to the centre of the measurements behind the height
  std::size_t known_ = 0;
};

/// The elevation map and the occupancy octree, fed together.
class TerrainMap {
 public:
  explicit TerrainMap(const MapperConfig& config);
  ~TerrainMap();
  TerrainMap(TerrainMap&&) noexcept;
  TerrainMap& operator=(TerrainMap&&) noexcept;

  /// Moves both maps' windows with the robot (ElevationMap::Recenter; the octree drops what
  /// leaves the window).
  void Recenter(const Eigen::Vector2d& robot_xy);
  /// Integrates one cloud: every finite return within max_range_m into the octree (free along
  /// its ray, occupied at its end) and into the elevation map with the variance of its height,
  /// sigma^2 (d_z^2 + 0.25 (1 - d_z^2)) + min_variance_m2 for range noise sigma and unit ray
  /// direction d (the vertical part of the range error, and a quarter of the horizontal part's
  /// variance: a point moved sideways reports a neighbouring place's height, so a horizontal ray on
  /// a block's side never fuses as an exact height); then a known cell where this cloud saw a
  /// surface below its height, and whose height the rays showed free (the voxels half a voxel above
  /// and below it at most clear_probability occupied), is forgotten. Places the window around the
  /// sensor when Recenter never did. Throws InputError when the origin is not finite, the range
  /// noise is negative or the cloud has more than max_points_per_cloud points (the map is unchanged).
  IntegrateReport Integrate(const WorldCloud& cloud);
  /// A stance foot measures the terrain under it: the cells within foot_patch_radius_m of
  /// `contact` (the lowest point of the foot's sphere) take its height with `variance`.
  void IntegrateContact(const Eigen::Vector3d& contact, double variance);
  /// The terrain under a robot standing on `feet` (its stance feet's contact points, at least
  /// three) before any sensor saw it: the unknown cells inside the feet's polygon, or within
  /// `margin_m` of it, take the height of the plane through the feet (least squares) with
  /// `variance`. For a map's start: the sensors do not look under the trunk, and the robot stands
  /// there.
  void InitializeFootprint(const std::vector<Eigen::Vector3d>& feet, double margin_m, double variance);

  const ElevationMap& elevation() const { return elevation_; }
  /// The known terrain as a mesh: the elevation map's (ElevationMap::ToMesh), with the cells
  /// under an obstacle raised. A depth camera sees a wall's face from the side: its cells hold
  /// face heights, and its top may never come into view. Where the octree holds an occupied
  /// voxel more than obstacle_rise_m above a cell's height in the cell's column, the cell is
  /// meshed at that voxel's top, and unseen_top_m higher when the voxel above it is unknown (the
  /// top never seen), so that planners checking collisions against the mesh keep clear of it.
  /// The elevation map itself keeps the measured heights.
  TriangleMesh ToMesh() const;
  /// Both maps' memory, as their containers hold it.
  std::size_t MemoryBytes() const;
  std::size_t OccupancyNodes() const;

 private:
  MapperConfig config_;
  ElevationMap elevation_;
  struct Occupancy;
  std::unique_ptr<Occupancy> occupancy_;  ///< the octomap::OcTree (kept out of this header)
};

/// The map judged against the true terrain. A cell holds one height; where the truth has several
/// within the cell (an edge runs through it), the map's height is right when it is one of them. So
/// a known cell's error is the map's height minus the truth's top (the highest point of `truth`
/// straight below) at the one of 5 x 5 points evenly inside the cell, its centre among them, where
/// that difference is smallest; cells with no truth below any of these points are counted apart.
/// A height no point of the cell has (a wall's face height, a block's edge smeared across a
/// cell boundary) counts in full.
struct HeightError {
  std::size_t cells = 0;           ///< known cells with truth below them
  std::size_t cells_no_truth = 0;  ///< known cells over no terrain at all
  double rms_m = 0.0;
  double p95_m = 0.0;              ///< 95th percentile of |error|
  double max_m = 0.0;
};
HeightError MeasureHeightError(const ElevationMap& map, const TriangleMesh& truth);

/// The share of the points of `path` (x, y) whose cells within `radius_m` are all known: how much
/// of the walked path the map covered.
double PathCoverage(const ElevationMap& map, const std::vector<Eigen::Vector2d>& path, double radius_m);

// ---- The configuration's fields, in the order of config/mapper.yaml ----

template <class Visitor>
void ElevationMapConfig::Serialize(Visitor* v) {
  v->Visit("resolution_m", &resolution_m, "m", bounds::Closed(0.005, 1.0), "side of a cell");
  v->Visit("window_m", &window_m, "m", bounds::Positive(), "side of the square window around the robot");
  const double cells = window_m / resolution_m;
  v->Rule("window_m", cells >= 4.0 && cells <= 4000.0, "between 4 and 4000 cells of resolution_m per side",
          ConfigNumber(window_m) + " (" + ConfigNumber(cells) + " cells)");
  v->Visit("recenter_distance_m", &recenter_distance_m, "m", bounds::Positive().Below(0.5 * window_m, "window_m / 2"),
           "the window moves (in whole cells) when the robot is this far from its centre");
  v->Visit("min_variance_m2", &min_variance_m2, "m^2", bounds::Positive(),
           "a cell's variance never falls below this (no estimate is exact)");
  v->Visit("gate_sigma", &gate_sigma, "-", bounds::Positive(),
           "a point this many standard deviations above a cell's height replaces it, as far below is not fused");
  v->Visit("mesh_smoothing_step_m", &mesh_smoothing_step_m, "m", bounds::NonNegative(),
           "the mesh's height of a cell is the variance-weighted mean of its 3 x 3 neighbours within this of its own "
           "height (an edge-preserving smoothing; 0: the fused heights as they are)");
  v->Visit("plane_step_m", &plane_step_m, "m", bounds::NonNegative(),
           "the mesh's planes: regions grown from flat patches over cells (8-neighbours) that step at most this "
           "from the cell they join from and lie within this of the region's plane (0: no planes)");
  v->Visit("plane_max_rms_m", &plane_max_rms_m, "m", bounds::NonNegative(),
           "a region whose cells lie this close to its least-squares plane (RMS) is meshed on that plane");
  v->Visit("plane_min_cells", &plane_min_cells, "-", bounds::AtLeast(3),
           "a region of fewer cells is not made a plane");
  v->Visit("mesh_fill_neighbours", &mesh_fill_neighbours, "-", bounds::Closed(1, 9),
           "an unknown cell with at least this many of its 8 neighbours on one of the mesh's planes is meshed on that "
           "plane, in two rounds (a hole between rays of up to two cells; 9: never)");
}

template <class Visitor>
void OccupancyConfig::Serialize(Visitor* v) {
  v->Visit("resolution_m", &resolution_m, "m", bounds::Closed(0.01, 1.0), "side of the octree's smallest voxel");
  v->Visit("max_range_m", &max_range_m, "m", bounds::Positive(), "rays are integrated up to this far from the sensor");
  v->Visit("clear_probability", &clear_probability, "-", bounds::Open(0.0, 0.5),
           "a cell whose height lies in a voxel at most this likely occupied is forgotten");
  v->Visit("obstacle_rise_m", &obstacle_rise_m, "m", bounds::Positive(),
           "the mesh raises a cell to the top of the occupied voxels standing more than this above its height in its "
           "column (a wall's face seen from the side)");
  v->Visit("unseen_top_m", &unseen_top_m, "m", bounds::NonNegative(),
           "... and this much higher when the voxel above that top is unknown (a top the sensors never saw)");
}

template <class Visitor>
void MapperConfig::Serialize(Visitor* v) {
  v->Visit("elevation", &elevation, "the 2.5D elevation map: height and variance per cell");
  v->Visit("occupancy", &occupancy, "the 3D occupancy octree that clears what rays pass through");
  v->Visit("publish_period_s", &publish_period_s, "s", bounds::Positive(),
           "TERRAIN and ELEVATION_MAP go out this often, of the clouds' (simulated) time");
  v->Visit("max_points_per_cloud", &max_points_per_cloud, "-", bounds::Closed(1, 10000000),
           "a larger cloud is rejected whole");
  v->Visit("foot_patch_radius_m", &foot_patch_radius_m, "m", bounds::Closed(0.0, 0.5),
           "a stance foot's sole marks the cells within this radius of its contact point");
}

inline MapperConfig MapperConfig::Load(const YamlMap& map) { return LoadConfig<MapperConfig>(map); }
inline MapperConfig MapperConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
inline void MapperConfig::Validate(const std::string& where) const { ValidateConfig(*this, where); }

}  // namespace rbcp::mapping
