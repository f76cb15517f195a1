#pragma once
/// Leg range-of-motion shapes (ROMs): the convex region, in the base frame, that a leg's foot
/// contact point can reach within the planning joint bounds without the leg hitting the trunk.
///
/// Generation: leg configurations are drawn uniformly within the planning joint bounds (seeded
/// std::mt19937_64); a configuration is rejected when the leg hits the trunk (its leg-trunk pairs
/// of RobotCollisionModel, RobotSelfCollision::CheckLegTrunk); the foot contact points of the rest are
/// wrapped in their convex hull (Qhull), which is simplified to at most `max_triangles` triangles
/// (an inner approximation, so never larger than the true hull) and finally scaled by `scale`
/// about the shape's volume centroid or the leg's HAA joint origin.

#include <array>
#include <optional>
#include <cstdint>
#include <string>
#include <vector>

#include "rbcp/core/leg.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/root_planner/convex_polytope.h"

namespace rbcp {

class RobotModel;

/// Parameters of ROM generation.
struct RomGenerationConfig {
  enum class ScaleCenter { kCentroid, kHip };

  int samples = 20000;                       ///< leg configurations drawn per leg, >= 100
  std::uint64_t seed = 1;                    ///< seed of the configuration sampler
  int max_triangles = 200;                   ///< triangle budget of the simplified hull, >= 4
  double tolerance = 0.002;                  ///< [m] simplification stops when no hull vertex is farther out
  double scale = 0.85;                       ///< scale factor, in (0, 1]
  ScaleCenter scale_center = ScaleCenter::kCentroid;
  bool reject_self_collisions = true;        ///< reject configurations where the leg hits the trunk
  /// Optional foot box relative to the leg's reference foot position (base frame): samples whose
  /// foot lies outside it are dropped, so the shape covers only the footholds the contact planner
  /// may use (its explicit step workspace) instead of everything the joints can reach.
  struct FootBox {
    double forward = 0.0, backward = 0.0;  ///< [m] along base +x / -x
    double outward = 0.0, inward = 0.0;    ///< [m] away from / toward the body's centre line
    double up = 0.0, down = 0.0;           ///< [m] along base +z / -z
  };
  std::optional<FootBox> foot_box;

  /// Reads every key above (scale_center: "centroid" or "hip"); strict.
  static RomGenerationConfig Load(const YamlMap& map);
  static RomGenerationConfig LoadFile(const std::string& path);
  /// One line per parameter ("samples: 20000"), as written in the ROM file header.
  std::vector<std::string> Describe() const;
};

/// What a ROM generation produced, for reports.
struct RomGenerationReport {
  int accepted_samples = 0;
  int rejected_samples = 0;   ///< self-collisions
  int outside_foot_box = 0;   ///< samples dropped by the foot box
  int full_hull_triangles = 0;
  double full_hull_volume = 0.0;        ///< [m^3] before simplification and scaling
  double simplified_volume = 0.0;       ///< [m^3] after simplification, before scaling
};

/// The foot contact points (base frame) of the accepted samples of one leg.
std::vector<Eigen::Vector3d> SampleFootPositions(const RobotModel& robot, Leg leg, const RomGenerationConfig& config,
                                                 RomGenerationReport* report = nullptr);

/// The ROM of one leg, in the base frame.
ConvexPolytope GenerateRom(const RobotModel& robot, Leg leg, const RomGenerationConfig& config,
                           RomGenerationReport* report = nullptr);

/// File name of a leg's ROM in a ROM folder: "<folder>/<LEG>.obj".
std::string RomPath(const std::string& folder, Leg leg);

/// Reads the four ROMs (LF, RF, LH, RH) of a folder. Throws InputError.
std::array<ConvexPolytope, kNumLegs> LoadRoms(const std::string& folder);

}  // namespace rbcp
