#pragma once
/// Self-collision of the robot: the primitive pairs of a RobotCollisionModel tested with FCL's
/// narrow phase (libccd GJK/MPR), after the primitives' bounds and a few separating axes. No FCL
/// type leaks out of this header.
///
/// Thread safety and cost: every query is const and keeps its scratch space per thread, so one
/// instance may be shared by several threads. A thread's last placement of the primitives is kept:
/// a query whose joints differ from the thread's previous one (on the same instance) in one leg
/// places that leg's primitives only (a swing, or a leg sampled with the others still).

#include <memory>

#include "rbcp/collision/collision_report.h"
#include "rbcp/collision/robot_collision_model.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {

class RobotSelfCollision {
 public:
  /// `model` must be built from `robot`; both are copied. With measure_penetration false,
  /// CollisionReport::penetration stays 0 (measuring it costs a second FCL pass on a collision).
  RobotSelfCollision(const RobotModel& robot, RobotCollisionModel model, bool measure_penetration = true);
  /// The robot's exact primitives (no margins), penetration measured.
  explicit RobotSelfCollision(const RobotModel& robot);
  ~RobotSelfCollision();
  RobotSelfCollision(RobotSelfCollision&&) noexcept;
  RobotSelfCollision& operator=(RobotSelfCollision&&) noexcept;
  RobotSelfCollision(const RobotSelfCollision&) = delete;
  RobotSelfCollision& operator=(const RobotSelfCollision&) = delete;

  /// Every leg against the trunk (LegTrunkPairs) and against the other legs (LegLegPairs) at the
  /// joints q. Independent of the base pose.
  CollisionReport Check(const JointVector& q) const;
  /// The pairs of Check(q) that hold a primitive of `leg`: where a configuration differs from one
  /// that passed Check only in that leg's joints (a swing), the same verdict for less work.
  CollisionReport Check(const JointVector& q, Leg leg) const;
  /// `leg` against the trunk only (its LegTrunkPairs), whatever the other legs do.
  CollisionReport CheckLegTrunk(const JointVector& q, Leg leg) const;

  const RobotModel& Robot() const;
  const RobotCollisionModel& Model() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbcp
