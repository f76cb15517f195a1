#include "rbcp/collision/robot_collision_model.h"

#include "fcl_shape.h"
#include "rbcp/core/error.h"

namespace rbcp {

using collision_detail::Aabb;
using collision_detail::FclShape;

namespace {

// Links whose pose changes when joint j of `leg` moves a little from the reference configuration.
std::vector<bool> LinksMovedBy(const RobotModel& robot, Leg leg, int j) {
  const JointVector q0 = robot.ReferenceConfiguration();
  JointVector q1 = q0;
  q1[kJointsPerLeg * Index(leg) + j] += 0.1;
  const auto p0 = robot.LinkPoses(q0);
  const auto p1 = robot.LinkPoses(q1);
  std::vector<bool> moved(p0.size(), false);
  for (std::size_t i = 0; i < p0.size(); ++i) moved[i] = !(p0[i].matrix() - p1[i].matrix()).isZero(1e-12);
  return moved;
}

// Which links each joint of each leg moves: [leg][joint][link].
using MovedLinks = std::array<std::array<std::vector<bool>, kJointsPerLeg>, kNumLegs>;

MovedLinks LinksMovedByEachJoint(const RobotModel& robot) {
  MovedLinks moved;
  for (Leg leg : kAllLegs) {
    for (int j = 0; j < kJointsPerLeg; ++j) {
      moved[static_cast<std::size_t>(Index(leg))][static_cast<std::size_t>(j)] = LinksMovedBy(robot, leg, j);
    }
  }
  return moved;
}

// The rigid body of a leg's link: the last of the leg's joints (HAA, HFE, KFE) that moves it.
RobotBody LegBody(const MovedLinks& moved, const CollisionShape& shape) {
  const auto link = static_cast<std::size_t>(shape.link_index);
  const auto& by_joint = moved[static_cast<std::size_t>(Index(*shape.leg))];
  constexpr std::array<RobotBody, kJointsPerLeg> kBodyOfJoint = {RobotBody::kHip, RobotBody::kThigh, RobotBody::kShank};
  for (int j = kJointsPerLeg - 1; j >= 0; --j) {
    if (by_joint[static_cast<std::size_t>(j)][link]) return kBodyOfJoint[static_cast<std::size_t>(j)];
  }
  throw InputError("robot collision model: expected the collision shape '" + shape.name + "' of link '" + shape.link +
                   "' on a link that a joint of leg " + std::string(LegName(*shape.leg)) + " moves, got a fixed one");
}

void Grow(CollisionPrimitive& p, double margin) {
  p.half_extents.array() += margin;
  p.radius += margin;
  p.half_length += margin;
}

}  // namespace

RobotCollisionModel::RobotCollisionModel(const RobotModel& robot, const CollisionMargins& margins) {
  RBCP_CHECK(margins.thigh >= 0.0 && margins.trunk >= 0.0, "robot collision model with a negative margin");
  ClassifyPrimitives(robot, margins);
  BuildPairs(robot);
}

void RobotCollisionModel::ClassifyPrimitives(const RobotModel& robot, const CollisionMargins& margins) {
  const MovedLinks moved = LinksMovedByEachJoint(robot);
  for (const CollisionShape& c : robot.CollisionShapes()) {
    CollisionPrimitive p;
    p.name = c.name.empty() ? c.link : c.name;
    p.link_index = c.link_index;
    p.leg = c.leg;
    p.body = c.leg ? LegBody(moved, c) : RobotBody::kTrunk;
    p.kind = c.kind;
    p.half_extents = 0.5 * c.box_size;
    p.radius = c.radius;
    p.half_length = 0.5 * c.length;
    p.pose_link = c.pose_link;
    if (p.body == RobotBody::kThigh) Grow(p, margins.thigh);
    if (p.body == RobotBody::kTrunk) Grow(p, margins.trunk);
    const int index = static_cast<int>(primitives_.size());
    if (p.leg) {
      legs_[static_cast<std::size_t>(Index(*p.leg))].push_back(index);
    } else {
      trunk_.push_back(index);
    }
    primitives_.push_back(std::move(p));
  }
}

void RobotCollisionModel::BuildPairs(const RobotModel& robot) {
  // The primitives placed in the reference configuration, for the overlaps by construction.
  const std::vector<Eigen::Isometry3d> link_poses = robot.LinkPoses(robot.ReferenceConfiguration());
  std::vector<FclShape> shapes;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Aabb> boxes;
  for (const CollisionPrimitive& p : primitives_) {
    shapes.emplace_back(p);
    poses.push_back(link_poses[static_cast<std::size_t>(p.link_index)] * p.pose_link);
    boxes.push_back(shapes.back().Bounds(poses.back()));
  }
  fcl::CollisionResultd result;
  const auto overlap_at_reference = [&](int a, int b) {
    const auto ia = static_cast<std::size_t>(a), ib = static_cast<std::size_t>(b);
    return collision_detail::ShapesTouch(shapes[ia], poses[ia], boxes[ia], shapes[ib], poses[ib], boxes[ib], result);
  };
  const auto body = [&](int i) { return primitives_[static_cast<std::size_t>(i)].body; };

  for (Leg leg : kAllLegs) {
    const auto l = static_cast<std::size_t>(Index(leg));
    for (int a : legs_[l]) {
      if (body(a) == RobotBody::kHip) continue;  // adjacent to the trunk
      for (int b : trunk_) (overlap_at_reference(a, b) ? reference_overlaps_ : leg_trunk_[l]).push_back({a, b});
    }
    for (int a : legs_[l]) {
      if (body(a) != RobotBody::kShank) continue;
      for (int h : legs_[l]) {
        if (body(h) == RobotBody::kHip) shank_hip_[l].push_back({a, h});
      }
    }
    for (std::size_t other = l + 1; other < legs_.size(); ++other) {
      for (int a : legs_[l]) {
        for (int b : legs_[other]) leg_leg_[l][other].push_back({a, b});
      }
    }
  }
}

const std::vector<PrimitivePair>& RobotCollisionModel::LegLegPairs(Leg a, Leg b) const {
  RBCP_CHECK(Index(a) < Index(b), "RobotCollisionModel::LegLegPairs: expected leg a before leg b");
  return leg_leg_[static_cast<std::size_t>(Index(a))][static_cast<std::size_t>(Index(b))];
}

}  // namespace rbcp
