#pragma once
// Self-collision filter of one leg, used to reject limb database samples.
//
// The pairs are the leg's in the robot's RobotCollisionModel (rbcp/collision): its thigh and
// shank primitives against the trunk's (LegTrunkPairs) and its shank's against its own hip's
// (ShankHipPairs). The other three legs are not tested: their configuration is only known when a
// contact is planned. The shank's pairs come first: a colliding sample is rejected soonest.
//
// Narrow phase: the primitives are tested as they are, boxes and spheres exactly, cylinders
// through their bounding capsule and bounding box (see convex_primitives.h), which never misses a
// collision and rarely reports a false one. The reference configuration must pass this test
// (the constructor checks it), so no tested pair overlaps by construction.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "convex_primitives.h"
#include "rbcp/collision/robot_collision_model.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp::limb_database_detail {

class LegSelfCollision {
 public:
  LegSelfCollision(const RobotModel& model, Leg leg);

  /// True when a checked pair overlaps with the leg at q_leg (HAA, HFE, KFE) [rad].
  /// Not thread-safe (reuses an internal pose buffer).
  bool InCollision(const Eigen::Vector3d& q_leg) const { return !FirstCollision(q_leg).first.empty(); }
  /// Names of the first overlapping pair (empty strings when the leg is free).
  std::pair<std::string, std::string> FirstCollision(const Eigen::Vector3d& q_leg) const;

  /// Number of primitive pairs tested per configuration.
  std::size_t NumPairs() const { return pairs_.size(); }
  /// "a / b" names of the tested pairs, for documentation and tests.
  std::vector<std::string> PairNames() const;

 private:
  ConvexPrimitive Posed(std::size_t primitive, const std::vector<Eigen::Isometry3d>& link_poses) const;
  const std::string& Name(int primitive) const {
    return collision_.Primitives()[static_cast<std::size_t>(primitive)].name;
  }

  const RobotModel& model_;
  RobotCollisionModel collision_;
  Leg leg_;
  std::vector<PrimitivePair> pairs_;
  std::vector<std::size_t> moving_shapes_;  // leg primitives taking part in some pair
  mutable JointVector q_;
  mutable std::vector<Eigen::Isometry3d> link_poses_;
  mutable std::vector<ConvexPrimitive> posed_;  // indexed like collision_.Primitives()
};

}  // namespace rbcp::limb_database_detail
