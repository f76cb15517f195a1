#include "rbcp/root_planner/rom.h"

#include <optional>
#include <random>

#include "rbcp/collision/robot_self_collision.h"
#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {

std::vector<std::string> RomGenerationConfig::Describe() const {
  // The fields in file order; a map's keys on its own line, as a flow map.
  std::vector<std::string> lines;
  bool in_left_out_map = false;
  for (const ConfigField& f : DescribeConfig(*this).fields) {
    const std::size_t dot = f.key.find('.');
    if (dot == std::string::npos) {
      in_left_out_map = f.value == "(left out)";
      const bool map = f.bounds.rfind("map", 0) == 0;
      if (!in_left_out_map) lines.push_back(f.key + ": " + (map ? "{}" : f.value));
    } else if (!in_left_out_map) {
      std::string& line = lines.back();
      line.insert(line.size() - 1, (line[line.size() - 2] == '{' ? "" : ", ") + f.key.substr(dot + 1) + ": " + f.value);
    }
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
