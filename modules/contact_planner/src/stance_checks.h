#pragma once
/// Tests of a stance at a base pose: where the base stands over the feet, whether each foot can be
/// kept (workspace, kinematics, collision), the static torques, the lift-off collision and the
/// base's straight motion between two states.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "path_track.h"
#include "planner_context.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/equilibrium/friction_cone.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp::contact_planner_detail {

using Feet = FootContacts;

/// A stance's base pose and the roll, pitch and yaw it is made of.
struct StanceBase {
  Eigen::Isometry3d base_W = Eigen::Isometry3d::Identity();  ///< rotation RotationFromRpy(rpy)
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
};

/// Base pose at a path pose, shifted horizontally by shift (path heading frame). With
/// base_pose.follow_feet the height and the roll and pitch follow the plane fitted through the
/// stance feet (least squares, in the heading frame), otherwise the base is level at the path
/// height; shift.z is added to the height in both cases. The height is then capped by
/// MarginHeightCeiling, the `lifting` leg (-1: none) at its lift-off distance.
StanceBase StanceBaseAt(const PlannerContext& ctx, const PathPose& pose, const Eigen::Vector3d& shift, const Feet& feet,
                        int lifting = -1);

/// The highest base height, at horizontal position p with orientation R, at which every foot
/// lies within the kinematic margins' stance distance of its hip, the `lifting` leg (-1: none)
/// within the lift-off distance (less a millimetre); +inf when some foot is beyond it
/// horizontally (that stance is rejected later anyway).
double MarginHeightCeiling(const PlannerContext& ctx, const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                           const Feet& feet, int lifting);

/// Largest workspace ratio of a foot at p_B (base frame); <= 1 inside.
double WorkspaceRatio(const PlannerContext& ctx, Leg leg, const Eigen::Vector3d& p_B);

/// Why a leg could not be kept.
enum class KeepFailure { kNone, kWorkspace, kKinematics, kCollision };

struct LegKeep {
  KeepFailure failure = KeepFailure::kNone;
  double stretch = 0.0;                      ///< WorkspaceRatio of the foot
  Eigen::Vector3d q = Eigen::Vector3d::Zero();  ///< the leg's joints (set when the IK succeeded)
};

/// Keeps a foot at foot_W with the base at base_W: workspace, IK within bounds, no collision.
LegKeep KeepLeg(const PlannerContext& ctx, Leg leg, const Eigen::Isometry3d& base_W, const Eigen::Vector3d& foot_W);

/// Marks a stance solved without the kinematic margins (a measured state, not a planned one).
inline constexpr int kNoMargins = -2;

/// IK of all four feet within the joint bounds (no workspace) and the kinematic margins,
/// `lifting` (-1: none) being the leg about to lift (it may stretch to the lift-off distance;
/// StanceChecker::SolveStance); with kNoMargins, within the joint bounds only. nullopt when a foot
/// cannot be reached.
std::optional<JointVector> SolveStance(const PlannerContext& ctx, const Eigen::Isometry3d& base_W, const Feet& feet,
                                       int lifting);

/// Centre of mass in the world frame.
inline Eigen::Vector3d CoM(const PlannerContext& ctx, const Eigen::Isometry3d& base_W, const JointVector& q) {
  return base_W * ctx.robot.CenterOfMass(q, &ctx.body_poses);
}

/// The feet as contact points, all but `skip` (-1: none).
std::vector<ContactPoint> Contacts(const Feet& feet, int skip);

/// The torques of the stance (all feet but `skip`) as the controller holds it
/// (StanceChecker::Torques).
inline StanceVerdict Torques(const PlannerContext& ctx, const Eigen::Isometry3d& base_W, const JointVector& q,
                             const Feet& feet, int skip, const Eigen::Vector3d& com_W) {
  return ctx.stance.Torques(base_W, q, feet, skip, com_W);
}

/// The CoM the stance rules' support margin inside the polygon of the feet but `skip`.
inline bool SupportHolds(const PlannerContext& ctx, const Feet& feet, int skip, const Eigen::Vector3d& com_W) {
  return ctx.stance.Support(feet, skip, com_W).ok();
}

}  // namespace rbcp::contact_planner_detail
