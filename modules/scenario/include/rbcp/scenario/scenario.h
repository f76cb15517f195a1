#pragma once
/// A benchmark scenario: the terrain the robot walks on, where its base starts and where it must go.
///
/// Scenario files are YAML, world frame, z up, metres and radians:
/// @code
/// name: darpa_rubble                 # letters, digits, '_' or '-'
/// terrain:                           # at least one element, kept in order
///   - box:  {size: [sx, sy, sz], position: [x, y, z], rpy: [r, p, y]}   # position = box centre
///   - mesh: {file: meshes/x.stl, position: [x, y, z], rpy: [r, p, y], scale: 1.0}
/// start: {position: [x, y], yaw: 0.0}   # base x, y; standing height comes from the terrain below
/// goal:  {position: [x, y], yaw: 0.0}
/// @endcode
/// Every key is required and no other key is accepted. Mesh files are STL, OBJ or PLY, with a path
/// relative to the scenario file (or absolute); the mesh is scaled first, then rotated by
/// Rz(yaw) * Ry(pitch) * Rx(roll), then translated. Start and goal must have terrain straight below.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "rbcp/core/triangle_mesh.h"

namespace rbcp {

class YamlMap;

/// A planar base pose: where the trunk starts or must arrive.
struct BaseGoal {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< base x, y in the world frame [m]
  double yaw = 0.0;                                    ///< heading about world z [rad]
};

/// A box obstacle: full edge lengths, centre and orientation in the world frame.
struct TerrainBox {
  Eigen::Vector3d size = Eigen::Vector3d::Ones();      ///< full edge lengths along the box axes [m]
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< box centre, world frame [m]
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();       ///< roll, pitch, yaw [rad]
};

/// A mesh obstacle read from a file.
struct TerrainMeshFile {
  std::string file;           ///< the path as written in the scenario file
  std::string resolved_path;  ///< the path used to open it (relative to the scenario file's folder)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< mesh origin, world frame [m]
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();       ///< roll, pitch, yaw [rad]
  double scale = 1.0;                                  ///< uniform scale applied before the pose
};

using TerrainElement = std::variant<TerrainBox, TerrainMeshFile>;

bool operator==(const BaseGoal& a, const BaseGoal& b);
bool operator==(const TerrainBox& a, const TerrainBox& b);
bool operator==(const TerrainMeshFile& a, const TerrainMeshFile& b);
inline bool operator!=(const BaseGoal& a, const BaseGoal& b) { return !(a == b); }
inline bool operator!=(const TerrainBox& a, const TerrainBox& b) { return !(a == b); }
inline bool operator!=(const TerrainMeshFile& a, const TerrainMeshFile& b) { return !(a == b); }

struct Scenario {
  std::string name;
  std::string path;  ///< the file it was loaded from; empty for a scenario built in code
  std::vector<TerrainElement> terrain;
  BaseGoal start;
  BaseGoal goal;
  /// Every terrain element as one world-frame mesh, in element order, outward winding.
  TriangleMesh terrain_mesh;
};

/// Reads and checks a scenario file. Throws InputError naming the file, the key and the problem.
Scenario LoadScenario(const std::string& path);

/// Parses scenario text as if it were the content of the file `path` (used in messages and to
/// resolve relative mesh paths; an empty path resolves them against the working directory).
Scenario ParseScenario(const std::string& yaml_text, const std::string& path);

/// Reads an STL, OBJ or PLY file with assimp (polygons triangulated, identical vertices joined,
/// node transforms applied), scales it and checks it with ValidateMesh. Points and lines in the
/// file are ignored. Throws InputError naming the file.
TriangleMesh LoadMeshFile(const std::string& path, double scale);

/// LoadMeshFile on the bytes of a mesh file read from `path` (whose extension names the format;
/// used in messages). Opens no file.
TriangleMesh ParseMeshFile(const std::string& bytes, const std::string& path, double scale);

/// The world-frame mesh of one element (reads mesh files).
TriangleMesh ElementMesh(const TerrainElement& element);

/// All elements as one world-frame mesh, in order.
TriangleMesh BuildTerrainMesh(const std::vector<TerrainElement>& terrain);

/// A base pose as a scenario file writes it ({position: [x, y], yaw}), strictly read.
BaseGoal ReadBasePose(const YamlMap& map);

/// The canonical text of a scenario: fixed key order, one element per line, numbers with at most
/// six decimals and no trailing zeros, so equal scenarios give identical bytes. Each entry of
/// `header_comments` becomes a leading "# ..." line.
std::string ScenarioToYaml(const Scenario& scenario, const std::vector<std::string>& header_comments = {});

/// The highest point of the mesh on the vertical line through xy [m], nullopt if no triangle
/// crosses it. Vertical triangles are ignored; points on a triangle edge count as inside.
std::optional<double> TerrainHeightAt(const TriangleMesh& mesh, const Eigen::Vector2d& xy);

/// TerrainHeightAt over a uniform xy grid of the mesh's triangles: the same answers, at the cost
/// of the triangles that overlap one cell. Copies what it needs from the mesh.
class TerrainHeightMap {
 public:
  /// Cells of cell_m [m] (enlarged so that the grid holds at most about a million cells).
  explicit TerrainHeightMap(const TriangleMesh& mesh, double cell_m = 0.025);
  /// The highest point of the mesh on the vertical line through xy [m], nullopt if none.
  std::optional<double> At(const Eigen::Vector2d& xy) const;
  bool Empty() const { return triangles_.empty(); }

 private:
  struct Triangle {
    Eigen::Vector3d a, b, c;
    Eigen::Vector2d lo, hi;  ///< xy bounds, widened by a micrometre (points on an edge belong to it)
  };
  std::vector<Triangle> triangles_;  // the non-vertical ones
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  double cell_ = 0.1;
  int nx_ = 0, ny_ = 0;
  std::vector<int> cell_start_;  // cell k lists cell_triangles_[cell_start_[k], cell_start_[k + 1])
  std::vector<int> cell_triangles_;
};

/// Triangles facing up (unit normal z >= min_normal_z) with other geometry above part of them:
/// such a face is covered by another solid and is not a real foothold. Each triangle is probed on
/// a grid of interior points; returns the indices of the covered ones.
std::vector<std::size_t> FindCoveredUpwardTriangles(const TriangleMesh& mesh, double min_normal_z = 0.5,
                                                    double tolerance = 1e-9);

}  // namespace rbcp
