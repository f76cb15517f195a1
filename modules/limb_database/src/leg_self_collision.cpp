#include "leg_self_collision.h"

#include <algorithm>

#include "rbcp/core/error.h"

namespace rbcp::limb_database_detail {

LegSelfCollision::LegSelfCollision(const RobotModel& model, Leg leg)
    : model_(model), collision_(model), leg_(leg), q_(model.ReferenceConfiguration()) {
  const auto body = [&](int i) { return collision_.Primitives()[static_cast<std::size_t>(i)].body; };
  for (const PrimitivePair& p : collision_.LegTrunkPairs(leg)) {
    if (body(p.a) == RobotBody::kShank) pairs_.push_back(p);
  }
  RBCP_CHECK(!pairs_.empty(), "the leg self-collision filter needs trunk and shank shapes");
  const auto& shank_hip = collision_.ShankHipPairs(leg);
  pairs_.insert(pairs_.end(), shank_hip.begin(), shank_hip.end());
  for (const PrimitivePair& p : collision_.LegTrunkPairs(leg)) {
    if (body(p.a) == RobotBody::kThigh) pairs_.push_back(p);
  }

  model.LinkPoses(q_, &link_poses_);
  posed_.resize(collision_.Primitives().size());
  for (std::size_t s = 0; s < posed_.size(); ++s) posed_[s] = Posed(s, link_poses_);
  for (const PrimitivePair& p : pairs_) {
    const auto a = static_cast<std::size_t>(p.a);
    if (std::find(moving_shapes_.begin(), moving_shapes_.end(), a) == moving_shapes_.end()) moving_shapes_.push_back(a);
  }
  for (int i : collision_.LegPrimitives(leg)) {
    if (body(i) == RobotBody::kHip) moving_shapes_.push_back(static_cast<std::size_t>(i));
  }
  const auto first = FirstCollision(LegJoints(model.ReferenceConfiguration(), leg));
  if (!first.first.empty()) {
    throw InputError("limb database: the reference configuration of leg " + std::string(LegName(leg)) +
                     " is in self-collision (" + first.first + " / " + first.second +
                     "); expected a collision-free reference stance");
  }
}

ConvexPrimitive LegSelfCollision::Posed(std::size_t primitive, const std::vector<Eigen::Isometry3d>& link_poses) const {
  const CollisionPrimitive& s = collision_.Primitives()[primitive];
  const Eigen::Isometry3d pose = link_poses[static_cast<std::size_t>(s.link_index)] * s.pose_link;
  ConvexPrimitive p;
  p.centre = pose.translation();
  p.axes = pose.linear();
  switch (s.kind) {
    case CollisionShape::Kind::kBox:
      p.kind = ConvexPrimitive::Kind::kBox;
      p.half = s.half_extents;
      break;
    case CollisionShape::Kind::kCylinder:
      p.kind = ConvexPrimitive::Kind::kCylinder;
      p.half = Eigen::Vector3d(0.0, 0.0, s.half_length);
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
  for (const PrimitivePair& p : pairs_) {
    if (PrimitivesOverlap(posed_[static_cast<std::size_t>(p.a)], posed_[static_cast<std::size_t>(p.b)])) {
      return {Name(p.a), Name(p.b)};
    }
  }
  return {};
}

std::vector<std::string> LegSelfCollision::PairNames() const {
  std::vector<std::string> names;
  for (const PrimitivePair& p : pairs_) names.push_back(Name(p.a) + " / " + Name(p.b));
  return names;
}

}  // namespace rbcp::limb_database_detail
