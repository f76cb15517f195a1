#include "rbcp/root_planner/rom.h"

#include <optional>
#include <random>
#include <sstream>

#include "rbcp/collision/robot_self_collision.h"
#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {

RomGenerationConfig RomGenerationConfig::Load(const YamlMap& map) {
  RomGenerationConfig c;
  c.samples = map.Int("samples");
  if (c.samples < 100) map.Fail("samples", "expected at least 100, got " + std::to_string(c.samples));
  const int seed = map.Int("seed");
  if (seed < 0) map.Fail("seed", "expected a non-negative integer, got " + std::to_string(seed));
  c.seed = static_cast<std::uint64_t>(seed);
  c.max_triangles = map.Int("max_triangles");
  if (c.max_triangles < 4) map.Fail("max_triangles", "expected at least 4, got " + std::to_string(c.max_triangles));
  c.tolerance = map.Double("tolerance");
  if (!(c.tolerance >= 0.0)) map.Fail("tolerance", "expected a length >= 0 m, got " + std::to_string(c.tolerance));
  c.scale = map.Double("scale");
  if (!(c.scale > 0.0 && c.scale <= 1.0)) map.Fail("scale", "expected a factor in (0, 1], got " + std::to_string(c.scale));
  const std::string center = map.String("scale_center");
  if (center == "centroid") {
    c.scale_center = ScaleCenter::kCentroid;
  } else if (center == "hip") {
    c.scale_center = ScaleCenter::kHip;
  } else {
    map.Fail("scale_center", "expected 'centroid' or 'hip', got '" + center + "'");
  }
  c.reject_self_collisions = map.Bool("reject_self_collisions");
  if (map.Has("foot_box")) {
    const YamlMap box = map.Map("foot_box");
    FootBox b;
    const auto extent = [&](const char* key) {
      const double v = box.Double(key);
      if (!(v > 0.0)) box.Fail(key, "expected a positive length [m], got " + std::to_string(v));
      return v;
    };
    b.forward = extent("forward");
    b.backward = extent("backward");
    b.outward = extent("outward");
    b.inward = extent("inward");
    b.up = extent("up");
    b.down = extent("down");
    box.RejectUnknownKeys();
    c.foot_box = b;
  }
  map.RejectUnknownKeys();
  return c;
}

RomGenerationConfig RomGenerationConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

std::vector<std::string> RomGenerationConfig::Describe() const {
  std::ostringstream scale_text;
  scale_text << scale;
  std::ostringstream tolerance_text;
  tolerance_text << tolerance;
  std::vector<std::string> lines = {"samples: " + std::to_string(samples),
          "seed: " + std::to_string(seed),
          "max_triangles: " + std::to_string(max_triangles),
          "tolerance: " + tolerance_text.str(),
          "scale: " + scale_text.str(),
          std::string("scale_center: ") + (scale_center == ScaleCenter::kCentroid ? "centroid" : "hip"),
          std::string("reject_self_collisions: ") + (reject_self_collisions ? "true" : "false")};
  if (foot_box) {
    std::ostringstream box;
    box << "foot_box: {forward: " << foot_box->forward << ", backward: " << foot_box->backward
        << ", outward: " << foot_box->outward << ", inward: " << foot_box->inward << ", up: " << foot_box->up
        << ", down: " << foot_box->down << "}";
    lines.push_back(box.str());
  }
  return lines;
}

std::vector<Eigen::Vector3d> SampleFootPositions(const RobotModel& robot, Leg leg, const RomGenerationConfig& config,
                                                 RomGenerationReport* report) {
  // One generator per leg, derived from the seed and the leg, so each leg's shape depends only
  // on its own parameters.
  std::seed_seq seq{static_cast<std::uint32_t>(config.seed & 0xffffffffu), static_cast<std::uint32_t>(config.seed >> 32),
                    static_cast<std::uint32_t>(Index(leg))};
  std::mt19937_64 rng(seq);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector3d lo = robot.LegLowerBounds(leg);
  const Eigen::Vector3d hi = robot.LegUpperBounds(leg);
  // The leg against the trunk (the other legs' configurations are not known here).
  std::optional<RobotSelfCollision> collision;
  if (config.reject_self_collisions) collision.emplace(robot, RobotCollisionModel(robot), /*measure_penetration=*/false);
  JointVector q_robot = robot.ReferenceConfiguration();
  std::vector<Eigen::Vector3d> feet;
  feet.reserve(static_cast<std::size_t>(config.samples));
  int rejected = 0;
  int outside = 0;
  const Eigen::Vector3d reference = robot.ReferenceFootPosition(leg);
  const double left = LeftSign(leg);
  const auto in_box = [&](const Eigen::Vector3d& foot) {
    if (!config.foot_box) return true;
    const RomGenerationConfig::FootBox& b = *config.foot_box;
    const Eigen::Vector3d d = foot - reference;
    const double out = left * d.y();
    return d.x() <= b.forward && -d.x() <= b.backward && out <= b.outward && -out <= b.inward && d.z() <= b.up &&
           -d.z() <= b.down;
  };
  for (int i = 0; i < config.samples; ++i) {
    Eigen::Vector3d q;
    for (int j = 0; j < 3; ++j) q[j] = lo[j] + unit(rng) * (hi[j] - lo[j]);
    SetLegJoints(q_robot, leg, q);
    if (collision && collision->CheckLegTrunk(q_robot, leg).collision) {
      ++rejected;
      continue;
    }
    const Eigen::Vector3d foot = robot.FootPosition(leg, q);
    if (!in_box(foot)) {
      ++outside;
      continue;
    }
    feet.push_back(foot);
  }
  if (report != nullptr) {
    report->accepted_samples = static_cast<int>(feet.size());
    report->rejected_samples = rejected;
    report->outside_foot_box = outside;
  }
  return feet;
}

ConvexPolytope GenerateRom(const RobotModel& robot, Leg leg, const RomGenerationConfig& config,
                           RomGenerationReport* report) {
  RomGenerationReport local;
  const std::vector<Eigen::Vector3d> feet = SampleFootPositions(robot, leg, config, &local);
  const ConvexPolytope full = ConvexHull(feet);
  local.full_hull_triangles = static_cast<int>(full.triangles.size());
  local.full_hull_volume = full.Volume();
  const ConvexPolytope simplified = SimplifiedConvexHull(full.vertices, config.max_triangles, config.tolerance);
  local.simplified_volume = simplified.Volume();
  const Eigen::Vector3d center =
      config.scale_center == RomGenerationConfig::ScaleCenter::kCentroid ? simplified.Centroid() : robot.HipPosition(leg);
  if (report != nullptr) *report = local;
  return simplified.Scaled(config.scale, center);
}

std::string RomPath(const std::string& folder, Leg leg) { return folder + "/" + std::string(LegName(leg)) + ".obj"; }

std::array<ConvexPolytope, kNumLegs> LoadRoms(const std::string& folder) {
  std::array<ConvexPolytope, kNumLegs> roms;
  for (Leg leg : kAllLegs) roms[static_cast<std::size_t>(Index(leg))] = LoadConvexObj(RomPath(folder, leg));
  return roms;
}

}  // namespace rbcp
