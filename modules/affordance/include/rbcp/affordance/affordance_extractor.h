#pragma once
/// Affordance extraction: the terrain mesh becomes convex planar contact surfaces the feet may
/// push on (inclination limit, minimum area, eroded away from edges).
///
/// Algorithm, in world frame:
///  1. Triangles facing up within `max_inclination_deg` of +z are candidates; the others (walls,
///     downward faces, degenerate triangles) never support a foot.
///  2. Candidate vertices closer than kWeldTolerance are welded into one, so the triangles of one
///     surface share edges even when the mesh is a triangle soup or is made of separate parts.
///  3. Regions grow over shared edges (not shared vertices) from a seed triangle, taken in
///     triangle-index order. A triangle joins when its normal is within `neighbour_angle_deg`
///     of the SEED normal (so a curved surface cannot drift) and its vertices are within
///     kCoplanarTolerance of the seed plane.
///  4. A region is kept when its area-weighted normal is within `max_inclination_deg` of +z and
///     its area exceeds `min_area`. Its plane has that normal and passes through the
///     area-weighted centroid.
///  5. The region boundary (edges used once in the region, chained into an outer ring and holes)
///     is projected into the plane and eroded by `edge_margin`: every remaining point is at
///     least `edge_margin` from the boundary. A convex region without holes is eroded exactly by
///     intersecting its inward-shifted edge half-planes. Other regions are offset inward with
///     round joins at reflex corners; each arc is replaced by chords tangent to it
///     (kErosionArcSegmentsPerCircle per full turn), so the result stays inside the exact erosion.
///  6. Eroded pieces with area <= `min_area` are dropped. Non-convex ones are triangulated (ear
///     clipping, holes bridged) and the triangles merged into convex polygons (Hertel-Mehlhorn).
///
/// Output order is deterministic: by region seed triangle, then piece order.
/// Coplanar parts of separate meshes become one surface only where their vertices coincide
/// (two equal boxes side by side share their top corners and merge into one rectangle); parts
/// that merely touch along an edge without shared corners (a T-junction) stay separate surfaces,
/// each eroded at the seam.

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "rbcp/affordance/affordance_config.h"
#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/triangle_mesh.h"

namespace rbcp {

/// Vertices closer than this are one vertex for adjacency [m].
inline constexpr double kWeldTolerance = 1e-6;
/// A triangle joins a region only if its vertices are this close to the seed plane [m].
inline constexpr double kCoplanarTolerance = 1e-3;
/// Triangles with a smaller area are ignored [m^2].
inline constexpr double kMinTriangleArea = 1e-12;
/// Round joins of the erosion at reflex corners use this many chords per full turn.
inline constexpr int kErosionArcSegmentsPerCircle = 16;

/// What the last Extract() call saw; counts only, cheap to keep.
struct AffordanceStats {
  int triangles = 0;             ///< triangles in the terrain mesh
  int degenerate_triangles = 0;  ///< ignored: area below kMinTriangleArea or beyond double range,
                                 ///< or two corners within kWeldTolerance
  int duplicate_triangles = 0;   ///< ignored: the same welded corners as a triangle taken before
  int candidate_triangles = 0;   ///< facing up within the inclination limit, not degenerate, not a duplicate
  int welded_vertices = 0;       ///< distinct candidate vertices after welding
  int planar_regions = 0;        ///< regions grown, before the inclination and area filters
  int kept_regions = 0;          ///< regions that passed the inclination and area filters
  int convex_regions = 0;        ///< kept regions eroded on the exact convex path
  int vanished_regions = 0;      ///< kept regions of which erosion left nothing above min_area
  int geometry_failures = 0;     ///< non-convex regions or pieces dropped because offsetting or
                                 ///< triangulating them failed (self-overlapping input)
  int surfaces = 0;              ///< convex surfaces returned
};

/// Extracts support surfaces from a terrain mesh. Holds its working memory between calls, so
/// one extractor per thread; Extract on the same input always gives the same output.
class AffordanceExtractor {
 public:
  /// Throws InputError if `config` is out of range (AffordanceConfig::Validate).
  explicit AffordanceExtractor(AffordanceConfig config);
  ~AffordanceExtractor();
  AffordanceExtractor(AffordanceExtractor&&) noexcept;
  AffordanceExtractor& operator=(AffordanceExtractor&&) noexcept;
  AffordanceExtractor(const AffordanceExtractor&) = delete;
  AffordanceExtractor& operator=(const AffordanceExtractor&) = delete;

  /// The contact surfaces of `terrain` (world frame, outward winding). Throws InputError
  /// ("terrain mesh: vertex 3 is not finite") for an empty mesh, a non-finite vertex or an
  /// out-of-range index.
  std::vector<AffordanceSurface> Extract(const TriangleMesh& terrain);
  /// Same, into `surfaces`, reusing its elements' memory.
  void Extract(const TriangleMesh& terrain, std::vector<AffordanceSurface>& surfaces);

  const AffordanceConfig& config() const { return config_; }
  const AffordanceStats& stats() const { return stats_; }

 private:
  struct Workspace;
  AffordanceConfig config_;
  AffordanceStats stats_;
  std::unique_ptr<Workspace> ws_;
};

}  // namespace rbcp
