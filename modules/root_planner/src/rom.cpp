#include "rbcp/root_planner/rom.h"

#include <fcl/narrowphase/collision.h>

#include <memory>
#include <random>

#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {
namespace {

std::shared_ptr<fcl::CollisionGeometryd> MakeGeometry(const CollisionShape& shape) {
  switch (shape.kind) {
    case CollisionShape::Kind::kBox:
      return std::make_shared<fcl::Boxd>(shape.box_size.x(), shape.box_size.y(), shape.box_size.z());
    case CollisionShape::Kind::kCylinder:
      return std::make_shared<fcl::Cylinderd>(shape.radius, shape.length);
    case CollisionShape::Kind::kSphere:
      return std::make_shared<fcl::Sphered>(shape.radius);
  }
  RBCP_CHECK(false, "unknown collision shape kind");
}

// Collision primitives of one leg against the trunk's, for the self-collision test.
class LegTrunkCollision {
 public:
  LegTrunkCollision(const RobotModel& robot, Leg leg) : robot_(robot), leg_(leg) {
    const std::string hip_link = std::string(LegName(leg)) + "_HIP";
    const auto& shapes = robot.CollisionShapes();
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      const CollisionShape& s = shapes[i];
      if (!s.leg) {
        trunk_.push_back(Entry{i, std::make_unique<fcl::CollisionObjectd>(MakeGeometry(s))});
      } else if (*s.leg == leg && s.link != hip_link) {
        // The hip link turns about the HAA axis fixed to the trunk: it is adjacent, not checked.
        leg_shapes_.push_back(Entry{i, std::make_unique<fcl::CollisionObjectd>(MakeGeometry(s))});
      }
    }
    // Pairs overlapping in the reference configuration overlap by design of the primitives.
    const JointVector q_ref = robot.ReferenceConfiguration();
    Place(q_ref);
    for (std::size_t a = 0; a < leg_shapes_.size(); ++a) {
      for (std::size_t b = 0; b < trunk_.size(); ++b) {
        if (!Collide(a, b)) pairs_.emplace_back(a, b);
      }
    }
  }

  bool Collides(const Eigen::Vector3d& q_leg) {
    JointVector q = robot_.ReferenceConfiguration();
    SetLegJoints(q, leg_, q_leg);
    Place(q);
    for (const auto& [a, b] : pairs_) {
      if (Collide(a, b)) return true;
    }
    return false;
  }

 private:
  struct Entry {
    std::size_t shape;
    std::unique_ptr<fcl::CollisionObjectd> object;
  };

  void Place(const JointVector& q) {
    robot_.LinkPoses(q, &poses_);
    const auto& shapes = robot_.CollisionShapes();
    for (auto* list : {&trunk_, &leg_shapes_}) {
      for (auto& e : *list) {
        const CollisionShape& s = shapes[e.shape];
        const Eigen::Isometry3d pose = poses_[static_cast<std::size_t>(s.link_index)] * s.pose_link;
        e.object->setTransform(pose.rotation(), pose.translation());
        e.object->computeAABB();
      }
    }
  }

  bool Collide(std::size_t a, std::size_t b) const {
    const auto& oa = *leg_shapes_[a].object;
    const auto& ob = *trunk_[b].object;
    if (!oa.getAABB().overlap(ob.getAABB())) return false;
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    return fcl::collide(&oa, &ob, request, result) > 0;
  }

  const RobotModel& robot_;
  Leg leg_;
  std::vector<Entry> trunk_;
  std::vector<Entry> leg_shapes_;
  std::vector<std::pair<std::size_t, std::size_t>> pairs_;
  std::vector<Eigen::Isometry3d> poses_;
};

}  // namespace

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
  std::unique_ptr<LegTrunkCollision> collision;
  if (config.reject_self_collisions) collision = std::make_unique<LegTrunkCollision>(robot, leg);
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
    if (collision && collision->Collides(q)) {
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
