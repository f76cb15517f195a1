#include "leg_self_collision.h"

#include <algorithm>

#include "rbcp/core/error.h"

namespace rbcp::limb_database_detail {
namespace {

/// Links of the leg whose pose changes when joint j moves by a small step from the reference.
std::vector<bool> LinksMovedBy(const RobotModel& model, Leg leg, int j) {
  const JointVector q0 = model.ReferenceConfiguration();
  JointVector q1 = q0;
  q1[kJointsPerLeg * Index(leg) + j] += 0.1;
  const auto p0 = model.LinkPoses(q0);
  const auto p1 = model.LinkPoses(q1);
  std::vector<bool> moved(p0.size(), false);
  for (std::size_t i = 0; i < p0.size(); ++i) {
    moved[i] = !(p0[i].matrix() - p1[i].matrix()).isZero(1e-12);
  }
  return moved;
}

}  // namespace

LegSelfCollision::LegSelfCollision(const RobotModel& model, Leg leg)
    : model_(model), leg_(leg), q_(model.ReferenceConfiguration()) {
  const auto& shapes = model.CollisionShapes();
  const std::vector<bool> moved_haa = LinksMovedBy(model, leg, 0);
  const std::vector<bool> moved_hfe = LinksMovedBy(model, leg, 1);
  const std::vector<bool> moved_kfe = LinksMovedBy(model, leg, 2);

  std::vector<std::size_t> trunk, hip, thigh, distal;
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const auto link = static_cast<std::size_t>(shapes[s].link_index);
    if (!shapes[s].leg) {
      trunk.push_back(s);
    } else if (*shapes[s].leg == leg) {
      if (moved_kfe[link]) {
        distal.push_back(s);
      } else if (moved_hfe[link]) {
        thigh.push_back(s);
      } else if (moved_haa[link]) {
        hip.push_back(s);
      }
    }
  }
  RBCP_CHECK(!trunk.empty() && !distal.empty(), "the leg self-collision filter needs trunk and shank shapes");

  model.LinkPoses(q_, &link_poses_);
  posed_.resize(shapes.size());
  for (std::size_t s = 0; s < shapes.size(); ++s) posed_[s] = Posed(s, link_poses_);

  for (std::size_t d : distal) {
    for (std::size_t t : trunk) pairs_.emplace_back(d, t);
    for (std::size_t h : hip) pairs_.emplace_back(d, h);
  }
  for (std::size_t th : thigh) {
    for (std::size_t t : trunk) {
      if (!PrimitivesOverlap(posed_[th], posed_[t])) pairs_.emplace_back(th, t);
    }
  }
  for (const auto& [a, b] : pairs_) {
    if (std::find(moving_shapes_.begin(), moving_shapes_.end(), a) == moving_shapes_.end()) {
      moving_shapes_.push_back(a);
    }
  }
  for (std::size_t h : hip) moving_shapes_.push_back(h);
  const auto first = FirstCollision(LegJoints(model.ReferenceConfiguration(), leg));
  if (!first.first.empty()) {
    throw InputError("limb database: the reference configuration of leg " + std::string(LegName(leg)) +
                     " is in self-collision (" + first.first + " / " + first.second +
                     "); expected a collision-free reference stance");
  }
}

ConvexPrimitive LegSelfCollision::Posed(std::size_t shape, const std::vector<Eigen::Isometry3d>& link_poses) const {
  const CollisionShape& s = model_.CollisionShapes()[shape];
  const Eigen::Isometry3d pose = link_poses[static_cast<std::size_t>(s.link_index)] * s.pose_link;
  ConvexPrimitive p;
  p.centre = pose.translation();
  p.axes = pose.linear();
  switch (s.kind) {
    case CollisionShape::Kind::kBox:
      p.kind = ConvexPrimitive::Kind::kBox;
      p.half = 0.5 * s.box_size;
      break;
    case CollisionShape::Kind::kCylinder:
      p.kind = ConvexPrimitive::Kind::kCylinder;
      p.half = Eigen::Vector3d(0.0, 0.0, 0.5 * s.length);
      p.radius = s.radius;
      break;
    case CollisionShape::Kind::kSphere:
      p.kind = ConvexPrimitive::Kind::kSphere;
      p.radius = s.radius;
      break;
  }
  return p;
}

std::pair<std::string, std::string> LegSelfCollision::FirstCollision(const Eigen::Vector3d& q_leg) const {
  SetLegJoints(q_, leg_, q_leg);
  model_.LinkPoses(q_, &link_poses_);
  for (std::size_t s : moving_shapes_) posed_[s] = Posed(s, link_poses_);
  const auto& shapes = model_.CollisionShapes();
  for (const auto& [a, b] : pairs_) {
    if (PrimitivesOverlap(posed_[a], posed_[b])) return {shapes[a].name, shapes[b].name};
  }
  return {};
}

std::vector<std::string> LegSelfCollision::PairNames() const {
  std::vector<std::string> names;
  const auto& shapes = model_.CollisionShapes();
  for (const auto& [a, b] : pairs_) names.push_back(shapes[a].name + " / " + shapes[b].name);
  return names;
}

}  // namespace rbcp::limb_database_detail
