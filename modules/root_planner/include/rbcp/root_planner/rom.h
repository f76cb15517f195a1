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

#include "rbcp/core/config_fields.h"
#include "rbcp/core/leg.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/root_planner/convex_polytope.h"

namespace rbcp {

class RobotModel;

/// Parameters of ROM generation (robots/anymal_b_roms/rom_generation.yaml).
struct RomGenerationConfig {
  enum class ScaleCenter { kCentroid, kHip };
  /// A box relative to the leg's reference foot position (base frame): samples whose foot lies
  /// outside it are dropped, so the shape covers only the footholds the contact planner may use
  /// (its explicit step workspace) instead of everything the joints can reach.
  struct FootBox {
    double forward = 1.0, backward = 1.0;
    double outward = 0.12, inward = 0.1;
    double up = 1.0, down = 1.0;

    template <class Visitor>
    void Serialize(Visitor* v) {
      v->Visit("forward", &forward, "m", bounds::Positive(), "along base +x");
      v->Visit("backward", &backward, "m", bounds::Positive(), "along base -x");
      v->Visit("outward", &outward, "m", bounds::Positive(), "away from the body's centre line");
      v->Visit("inward", &inward, "m", bounds::Positive(), "toward the body's centre line");
      v->Visit("up", &up, "m", bounds::Positive(), "along base +z");
      v->Visit("down", &down, "m", bounds::Positive(), "along base -z");
    }
  };

  int samples = 50000;
  std::uint64_t seed = 2019;
  int max_triangles = 200;
  double tolerance = 0.002;
  double scale = 1.0;
  ScaleCenter scale_center = ScaleCenter::kCentroid;
  bool reject_self_collisions = true;
  std::optional<FootBox> foot_box = FootBox();

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("samples", &samples, "", bounds::AtLeast(100), "leg configurations drawn per leg");
    v->Visit("seed", &seed, "", bounds::NonNegative(),
             "seed of the configuration sampler (each leg derives its own stream from it)");
    v->Visit("max_triangles", &max_triangles, "", bounds::AtLeast(4), "triangle budget of the simplified hull");
    v->Visit("tolerance", &tolerance, "m", bounds::NonNegative(),
             "the simplification stops once no hull vertex lies farther outside");
    v->Visit("scale", &scale, "", bounds::Positive().AtMost(1.0), "scale factor of the shape");
    v->Visit("scale_center", &scale_center, EnumNames<ScaleCenter>{{ScaleCenter::kCentroid, "centroid"},
                                                                  {ScaleCenter::kHip, "hip"}},
             "the point the shape is scaled about: its volume centroid or the HAA joint origin");
    v->Visit("reject_self_collisions", &reject_self_collisions,
             "configurations where the thigh, shank or foot hits the trunk are dropped");
    v->Visit("foot_box", &foot_box, "feet outside this box around the reference foot position are dropped");
  }

  /// Reads every key above (foot_box may be left out); strict.
  static RomGenerationConfig Load(const YamlMap& map) { return LoadConfig<RomGenerationConfig>(map); }
  static RomGenerationConfig LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
  /// One line per parameter ("samples: 50000", "foot_box: {forward: 1, ...}"), as written in the
  /// ROM file header.
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
