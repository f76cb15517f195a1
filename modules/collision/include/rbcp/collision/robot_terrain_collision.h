#pragma once
/// Collision checking of the ANYmal collision primitives against a terrain mesh and against
/// themselves. Broad phase: a uniform xy grid over the terrain triangles (cell height bounds,
/// triangle bounds, each triangle's plane against the primitive's extent along its normal).
/// Narrow phase: FCL's primitive-triangle and primitive-primitive tests (libccd GJK/MPR). No FCL
/// type leaks out of this header.
///
/// Terrain: the mesh is treated as the boundary of a solid (closed, outward-wound elements such as
/// the scenario boxes; elements may overlap). A robot shape collides when it touches a terrain
/// triangle or lies entirely inside the solid. Inside-ness is the winding number of a vertical ray
/// cast upwards from the shape's centre (each upward-facing triangle crossed above counts +1, each
/// downward-facing one -1), so overlapping elements count as one solid. For an open surface
/// (a terrain patch without underside) this reads as "below an upward-facing surface".
///
/// Feet in contact: a stance foot stands on the terrain, so its sphere may sink into it by up to
/// `foot_tolerance` (the planning contact point lies on the sphere along the shank axis, so a
/// shank tilted by an angle a from the surface normal sinks the sphere by r (1 - cos a)). It is
/// checked as a sphere shrunk by foot_tolerance about the same centre: exact "penetration depth
/// <= foot_tolerance" while the centre is outside the terrain; a centre inside is a collision.
/// The default 15 mm admits shank tilts up to ~59 degrees from the normal on a plane.
/// The adapter tube of a stance leg is checked without its last `adapter_exclusion` metres next to
/// the foot (the tube ends inside the foot sphere and dips below the contact plane as soon as the
/// shank tilts more than ~27 degrees from the normal; without its last 2 cm, beyond ~62 degrees).
/// Shanks, thighs and hips are always checked, and swing legs are checked whole.
///
/// Self-collision (CheckSelf): RobotSelfCollision over the pairs of the robot's
/// RobotCollisionModel, built with this checker's thigh and trunk margins: each leg against the
/// trunk and against the other legs, without the pairs that model leaves out (adjacent bodies,
/// pairs within one leg, leg-trunk pairs overlapping in the reference configuration).
///
/// Thread safety and cost: every query is const and keeps its scratch space per thread, so one
/// instance may be shared by several threads. Once warm, the library allocates nothing per query
/// itself; FCL's libccd narrow phase allocates two small objects per box or cylinder test that
/// passes the broad phase, and a report naming a shape copies the name.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rbcp/collision/collision_report.h"
#include "rbcp/collision/robot_self_collision.h"
#include "rbcp/core/leg.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {

/// Tolerances of the stance legs (see the file comment).
struct CollisionOptions {
  double foot_tolerance = 0.015;    ///< [m] penetration allowed to the foot sphere of a stance leg, in [0, radius)
  double adapter_exclusion = 0.02;  ///< [m] length of a stance leg's adapter tube not checked next to the foot
  /// [m] the thighs' primitives (with the knee actuators) are checked this much larger on every
  /// side, in [0, 0.1): a clearance for the knees, which pass close over block edges next to a
  /// foot on the floor. Self-collision pairs that the larger thighs overlap in the reference
  /// stance are then excluded, so an instance with a margin is meant for terrain checks.
  double thigh_margin = 0.0;
  /// [m] the trunk's primitives (body, belly plate, hip actuators) are checked this much larger on
  /// every side, in [0, 0.1): a clearance for a body that walks a centimetre or two off its plan
  /// past a riser or a block edge. As thigh_margin, meant for terrain checks.
  double trunk_margin = 0.0;
  /// Fill CollisionReport::penetration. Measuring the depth costs a second FCL pass on colliding
  /// queries (gathering every contact of the shape); planners that only need yes/no turn it off
  /// and get penetration == 0.
  bool measure_penetration = true;
};

class RobotTerrainCollision {
 public:
  /// Builds the terrain bounding-volume hierarchy and the robot's collision primitives once.
  /// Copies what it needs from `robot`; neither argument must outlive the object.
  /// Throws InputError when the terrain mesh is invalid (ValidateMesh), when a leg lacks a sphere
  /// on its <LEG>_FOOT link or a cylinder on its <LEG>_ADAPTER link, or when an option is out of range.
  RobotTerrainCollision(const RobotModel& robot, const TriangleMesh& terrain, const CollisionOptions& options = {});
  ~RobotTerrainCollision();
  RobotTerrainCollision(RobotTerrainCollision&&) noexcept;
  RobotTerrainCollision& operator=(RobotTerrainCollision&&) noexcept;
  RobotTerrainCollision(const RobotTerrainCollision&) = delete;
  RobotTerrainCollision& operator=(const RobotTerrainCollision&) = delete;

  /// Whole robot (trunk and four legs) at base pose base_W (base frame in world) and joints q
  /// against the terrain. feet_in_contact[Index(leg)] marks stance legs (foot tolerance applies).
  CollisionReport CheckRobot(const Eigen::Isometry3d& base_W, const JointVector& q,
                             const std::array<bool, kNumLegs>& feet_in_contact) const;

  /// One leg's shapes (hip, thigh, shank, adapter, foot) against the terrain.
  CollisionReport CheckLeg(Leg leg, const Eigen::Isometry3d& base_W, const Eigen::Vector3d& q_leg,
                           bool foot_in_contact) const;

  /// The trunk (the base link's shapes) against the terrain.
  CollisionReport CheckTrunk(const Eigen::Isometry3d& base_W) const;

  /// Self-collision: leg against leg (different legs) and leg against trunk
  /// (RobotSelfCollision::Check). Independent of the base pose.
  CollisionReport CheckSelf(const JointVector& q) const;
  /// The pairs of CheckSelf(q) that hold a shape of `leg`: where a configuration differs from
  /// one that passed CheckSelf only in that leg's joints (a swing), the same verdict for less work.
  CollisionReport CheckSelf(const JointVector& q, Leg leg) const;

  /// True when the world point p_W lies inside the terrain solid (vertical-ray winding number > 0).
  bool InsideTerrain(const Eigen::Vector3d& p_W) const;

  /// Leg-trunk shape pairs (leg shape name, trunk shape name) that CheckSelf does not test
  /// because they overlap in the reference configuration (RobotCollisionModel::ReferenceOverlaps);
  /// hip-trunk pairs are not listed.
  std::vector<std::pair<std::string, std::string>> SelfCollisionExclusions() const;

  const CollisionOptions& Options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbcp
