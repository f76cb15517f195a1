#pragma once
/// The one owner of what makes a stance and a step executable. The contact planner chooses only
/// stances and steps that pass these checks, the controller walks them as planned (the base on
/// the plan's poses, each foot on the swing path planned here) and the plan checker verifies
/// them, all with one configuration (StanceConfig) and the same force distribution, collision
/// model and swing path.
///
/// A step from state `from` to state `to` (to.moving_leg = L) is walked in four phases, each
/// checked by CheckStep:
///  - shift: the base moves in a straight line from from's pose to to's pose with the four feet
///    of `from` down; at StanceConfig::transit_checks poses in between every foot is in reach, the
///    CoM support_margin_m inside the four feet's polygon, the trunk clear of the terrain and the
///    stance torques below the ceiling;
///  - lift-off (the unload at to's base pose): the robot clear of the terrain (the lifting leg with
///    its exact shapes, as its knee rises from there) and of itself, the CoM inside the three
///    feet that stay, their torques below the ceiling;
///  - swing: L's foot follows the SwingTrajectory planned by PlanSwing from its old foothold to
///    its new one, with the base held at to's pose: the foot clear of the terrain under its path,
///    the leg clear of the terrain (thighs with their clearance) and, with swing.body_clearance,
///    of the trunk and the other legs;
///  - touch-down (and reload): the CoM inside the three feet with L at its new joints, the torques
///    of those three and of all four below the ceiling.
/// The stability LPs (robustness of static equilibrium) are the equilibrium library's, not part
/// of this.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/collision/robot_terrain_collision.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/stance/stance_config.h"
#include "rbcp/stance/swing_trajectory.h"

namespace rbcp {

using FootContacts = std::array<FootContact, kNumLegs>;

/// The feet's positions, all but `skip` (-1: none).
std::vector<Eigen::Vector3d> FeetPositions(const FootContacts& feet, int skip);

/// Which condition a stance or a step fails.
enum class StanceCheck {
  kOk,
  kReach,          ///< a foot out of its leg's reach (inverse kinematics, joint bounds, margins)
  kCollision,      ///< the robot, with its clearances, touches the terrain
  kSelfCollision,  ///< two robot shapes touch
  kSupport,        ///< the CoM closer than support_margin_m to the support polygon's edge
  kBalance,        ///< the feet's friction cones cannot hold the weight
  kTorque,         ///< a joint above the torque ceiling
  kSwingTerrain,   ///< the swinging foot or leg cannot keep clear of the terrain along its path
  kSwingBody,      ///< the swinging leg cannot keep clear of the trunk and the other legs
};

/// "ok", "reach", "collision", "self_collision", "support", "balance", "torque", "swing_terrain",
/// "swing_body".
const char* ToString(StanceCheck check);

/// The phase of a step a verdict is about (see the top of this file).
enum class StepPhase { kShift, kLiftOff, kSwing, kTouchDown };

/// "shift", "lift_off", "swing", "touch_down".
const char* ToString(StepPhase phase);

struct StanceVerdict {
  StanceCheck check = StanceCheck::kOk;
  StepPhase phase = StepPhase::kLiftOff;  ///< set by CheckStep
  std::string detail;                     ///< what was found, with numbers (empty when ok)
  std::optional<Leg> leg;                 ///< the leg concerned, where one is
  bool ok() const { return check == StanceCheck::kOk; }
  /// "<phase>: <check>: <detail>", or "ok".
  std::string Describe() const;
};

class StanceChecker {
 public:
  /// The robot must outlive the checker. Throws InputError for an invalid configuration.
  StanceChecker(const RobotModel& robot, const StanceRules& rules);
  ~StanceChecker();
  StanceChecker(StanceChecker&&) noexcept;
  StanceChecker& operator=(StanceChecker&&) noexcept;

  /// The terrain of the collision and swing checks (copied); null or empty: no terrain, and
  /// then no collision checks at all. Throws InputError for an invalid mesh.
  void SetTerrain(const TriangleMesh* terrain);
  bool HasTerrain() const { return terrain_ != nullptr; }

  const RobotModel& Robot() const { return *robot_; }
  const StanceRules& Rules() const { return rules_; }
  const StanceConfig& Config() const { return rules_.config; }
  /// torque_limit_fraction times the actuators' command limit [N m].
  double TorqueCeiling() const;

  /// Terrain checks with the thighs' and the trunk's clearances; requires HasTerrain().
  const RobotTerrainCollision& TerrainCollision() const;
  /// Exact shapes: self-collision, and a leg about to lift; requires HasTerrain().
  const RobotTerrainCollision& ExactCollision() const;

  /// The joints that put every foot on `feet` with the base at base_W, within the joint bounds
  /// and the kinematic margins (the `lifting` leg, -1: none, within its lift-off distance);
  /// nullopt when a foot cannot be reached so.
  std::optional<JointVector> SolveStance(const Eigen::Isometry3d& base_W, const FootContacts& feet, int lifting) const;

  /// The CoM support_margin_m inside the polygon of the feet but `skip` (-1: none).
  StanceVerdict Support(const FootContacts& feet, int skip, const Eigen::Vector3d& com_W) const;
  /// The torques that hold the robot still on the feet but `skip`, its weight at com_W spread
  /// as the controller spreads it: balanced, and every joint below TorqueCeiling(). *max_abs_Nm
  /// (optional) receives the largest |torque|, +inf when unbalanced.
  StanceVerdict Torques(const Eigen::Isometry3d& base_W, const JointVector& q, const FootContacts& feet, int skip,
                        const Eigen::Vector3d& com_W, double* max_abs_Nm = nullptr) const;
  /// The same for a CoM accelerating at com_acceleration_W: the feet push m (a - g).
  StanceVerdict Torques(const Eigen::Isometry3d& base_W, const JointVector& q, const FootContacts& feet, int skip,
                        const Eigen::Vector3d& com_W, const Eigen::Vector3d& com_acceleration_W,
                        double* max_abs_Nm = nullptr) const;
  /// The stance before `lifting` lifts off: the trunk and the stance legs clear of the terrain
  /// with their clearances, the lifting leg with its exact shapes (its knee rises from there),
  /// no self-collision. A stance leg on the terrain is the verdict's leg. Requires HasTerrain().
  StanceVerdict LiftOffCollision(const Eigen::Isometry3d& base_W, const JointVector& q, Leg lifting) const;

  /// The swing path of `leg` from from_W to to_W with the base held at base_W; q holds the other
  /// legs' joints (for the check against them: the swinging leg's self-collision pairs are tested,
  /// q's others are taken as checked, as LiftOffCollision does). Without a terrain, the plain path. kFirstClear:
  /// a planner's question (is there a clear path, and which), answered at a fraction of the cost.
  SwingTrajectory PlanSwing(Leg leg, const Eigen::Vector3d& from_W, const Eigen::Vector3d& to_W,
                            const Eigen::Isometry3d& base_W, const JointVector& q,
                            SwingSearch search = SwingSearch::kFewestFailures) const;
  /// Whether a path from PlanSwing keeps clear of the terrain (and the body, with
  /// swing.body_clearance).
  StanceVerdict SwingClearance(const SwingTrajectory& swing, Leg leg) const;

  /// The whole step from `from` to `to` as the controller walks it (see the top of this file):
  /// the first failing check, with its phase.
  StanceVerdict CheckStep(const WholeBodyState& from, const WholeBodyState& to) const;
  /// The shift phase alone: the base from from_base's pose to to_base (rotation rpy_to) on the
  /// four `feet`, `lifting` (-1: none) about to lift (its foot may stretch to the lift-off
  /// distance).
  StanceVerdict CheckShift(const Eigen::Vector3d& from_position, const Eigen::Vector3d& from_rpy,
                           const Eigen::Isometry3d& to_base, const Eigen::Vector3d& rpy_to, const FootContacts& feet,
                           int lifting) const;

 private:
  const RobotModel* robot_;
  StanceRules rules_;
  std::unique_ptr<RobotTerrainCollision> terrain_;  // with the clearances
  std::unique_ptr<RobotTerrainCollision> exact_;
  std::unique_ptr<TerrainHeightMap> heights_;
};

}  // namespace rbcp
