#pragma once
// Self-collision filter of one leg, used to reject limb database samples.
//
// The robot's URDF collision primitives are used as they are: boxes and spheres exactly, cylinders
// through their bounding capsule and bounding box (see convex_primitives.h), which never misses a
// collision and rarely reports a false one.
//
// Checked pairs (the other three legs stay at the reference configuration and are not tested:
// their configuration is only known when a contact is planned):
//  * every primitive of the leg's distal body (shank, adapter tube, foot: the links that move with
//    KFE) against every trunk primitive (main body, belly bumps, the four HAA actuators) and
//    against the primitives of the leg's own hip link (the links that move with HAA only);
//  * every primitive of the thigh (the links that move with HFE but not KFE) against the trunk
//    primitives that do not overlap it in the reference configuration (its own HAA actuator
//    touches the thigh's upper protector by construction and is skipped).
// Adjacent bodies (hip-thigh, thigh-shank) are never tested against each other: they overlap at
// their joints by construction.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "convex_primitives.h"
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
  ConvexPrimitive Posed(std::size_t shape, const std::vector<Eigen::Isometry3d>& link_poses) const;

  const RobotModel& model_;
  Leg leg_;
  std::vector<std::pair<std::size_t, std::size_t>> pairs_;  // indices into model_.CollisionShapes()
  std::vector<std::size_t> moving_shapes_;                  // leg shapes taking part in some pair
  mutable JointVector q_;
  mutable std::vector<Eigen::Isometry3d> link_poses_;
  mutable std::vector<ConvexPrimitive> posed_;  // indexed like model_.CollisionShapes()
};

}  // namespace rbcp::limb_database_detail
