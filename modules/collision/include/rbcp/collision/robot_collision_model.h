#pragma once
/// The robot's collision geometry, in one place: its primitives (RobotModel::CollisionShapes()),
/// the rigid body each one rides on, and the primitive pairs that can collide with each other.
/// Every self-collision test takes its primitives and pairs from here, each with its own narrow
/// phase:
///  - RobotSelfCollision (FCL), behind RobotTerrainCollision::CheckSelf: every leg's
///    LegTrunkPairs and every LegLegPairs, the whole robot at once (the plan checker, the contact
///    planner's stances and swings, the controller's swing paths);
///  - the leg range-of-motion shapes (SampleFootPositions, RobotSelfCollision::CheckLegTrunk):
///    one leg's LegTrunkPairs;
///  - the limb database's sample filter (its own convex overlap test): one leg's LegTrunkPairs
///    and ShankHipPairs.
///
/// Rigid bodies (RobotBody): the trunk (the base link and what is fixed to it, such as the HAA
/// actuators) and, per leg, the hip (the links that HAA moves and HFE does not), the thigh (that
/// HFE moves and KFE does not) and the shank (that KFE moves: shank, adapter tube and foot).
///
/// Pairs never tested, and why:
///  - two primitives of one body: they never move relative to each other;
///  - adjacent bodies (trunk-hip at HAA, hip-thigh at HFE, thigh-shank at KFE): their primitives
///    meet around the joint by construction;
///  - a thigh or shank primitive against a trunk primitive that it overlaps in the reference
///    configuration: they overlap by construction (each thigh around its own HAA actuator);
///    ReferenceOverlaps() lists them.
/// Pairs that only some tests take:
///  - LegLegPairs: the whole-robot tests. The limb database and the range-of-motion shapes sample
///    one leg with the others unknown, so they test that leg against the trunk alone.
///  - ShankHipPairs (a shank folded back onto its own hip): the limb database only. Within the
///    planning joint bounds the shank does not reach its hip (a test samples the bounds), so the
///    whole-robot tests, whose leg joints stay within them, leave these pairs out.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/leg.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {

/// The rigid body a collision primitive rides on (see the file comment).
enum class RobotBody { kTrunk, kHip, kThigh, kShank };

/// One collision primitive of the robot, placed on its link; cylinders have their axis along the
/// primitive frame's z.
struct CollisionPrimitive {
  std::string name;        ///< URDF collision name (the link name if unnamed)
  int link_index = -1;     ///< index into RobotModel::Links() and RobotModel::LinkPoses()
  std::optional<Leg> leg;  ///< nullopt on the trunk
  RobotBody body = RobotBody::kTrunk;
  CollisionShape::Kind kind = CollisionShape::Kind::kBox;
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  ///< [m] (box)
  double radius = 0.0;                                     ///< [m] (cylinder, sphere)
  double half_length = 0.0;                                ///< [m] along z (cylinder)
  Eigen::Isometry3d pose_link = Eigen::Isometry3d::Identity();  ///< primitive frame in the link frame
};

/// Two primitives that a self-collision test checks against each other: indices into
/// RobotCollisionModel::Primitives(), the leg's primitive (the earlier leg's) first.
struct PrimitivePair {
  int a = -1;
  int b = -1;
};

/// Clearances [m] grown on every side of the thighs' and the trunk's primitives (the terrain
/// checks' CollisionOptions::thigh_margin and trunk_margin). Self-collision pairs are decided on
/// the grown primitives, so the reference configuration stays free of self-collision.
struct CollisionMargins {
  double thigh = 0.0;
  double trunk = 0.0;
};

class RobotCollisionModel {
 public:
  /// Copies what it needs from `robot`. Throws InputError when a leg primitive rides on a link
  /// that none of its leg's joints moves; a negative margin is a caller error.
  explicit RobotCollisionModel(const RobotModel& robot, const CollisionMargins& margins = {});

  /// Every primitive, in RobotModel::CollisionShapes() order (trunk, then LF, RF, LH, RH, each
  /// from hip to foot).
  const std::vector<CollisionPrimitive>& Primitives() const { return primitives_; }
  /// Indices of the trunk's primitives.
  const std::vector<int>& Trunk() const { return trunk_; }
  /// Indices of a leg's primitives, hip to foot.
  const std::vector<int>& LegPrimitives(Leg leg) const { return legs_[static_cast<std::size_t>(Index(leg))]; }

  /// The leg's thigh and shank primitives against the trunk's, without ReferenceOverlaps(); in
  /// LegPrimitives(leg) order, each against the trunk in Trunk() order.
  const std::vector<PrimitivePair>& LegTrunkPairs(Leg leg) const {
    return leg_trunk_[static_cast<std::size_t>(Index(leg))];
  }
  /// Every primitive of leg `a` against every one of leg `b`; `a` must come before `b` in kAllLegs.
  const std::vector<PrimitivePair>& LegLegPairs(Leg a, Leg b) const;
  /// The leg's shank primitives against its own hip's.
  const std::vector<PrimitivePair>& ShankHipPairs(Leg leg) const {
    return shank_hip_[static_cast<std::size_t>(Index(leg))];
  }
  /// The leg-trunk pairs left out because they overlap in the reference configuration.
  const std::vector<PrimitivePair>& ReferenceOverlaps() const { return reference_overlaps_; }

 private:
  void ClassifyPrimitives(const RobotModel& robot, const CollisionMargins& margins);
  void BuildPairs(const RobotModel& robot);

  std::vector<CollisionPrimitive> primitives_;
  std::vector<int> trunk_;
  std::array<std::vector<int>, kNumLegs> legs_;
  std::array<std::vector<PrimitivePair>, kNumLegs> leg_trunk_;
  std::array<std::vector<PrimitivePair>, kNumLegs> shank_hip_;
  std::array<std::array<std::vector<PrimitivePair>, kNumLegs>, kNumLegs> leg_leg_;  // [a][b], a before b
  std::vector<PrimitivePair> reference_overlaps_;
};

}  // namespace rbcp
