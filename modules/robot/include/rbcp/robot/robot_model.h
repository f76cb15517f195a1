#pragma once
/// The ANYmal robot model: joint tree, masses and collision primitives from a URDF, planning
/// parameters (reference stance, planning joint bounds, foot contact point, limits) from a YAML
/// file. Leg kinematics (forward, Jacobian, analytic inverse) and whole-body centre of mass.
///
/// Frames: the base frame has x forward, y left, z up. Joint values are [rad], lengths [m].
/// A leg's joints are (HAA, HFE, KFE); the whole-robot joint vector is LF, RF, LH, RH.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/leg.h"

namespace rbcp {

inline constexpr int kJointsPerLeg = 3;
inline constexpr int kNumJoints = kNumLegs * kJointsPerLeg;

/// Whole-robot joint vector [rad]: LF, RF, LH, RH, each (HAA, HFE, KFE).
using JointVector = Eigen::Matrix<double, kNumJoints, 1>;

/// The three joints of one leg taken from a whole-robot joint vector.
inline Eigen::Vector3d LegJoints(const JointVector& q, Leg leg) { return q.segment<3>(kJointsPerLeg * Index(leg)); }
inline void SetLegJoints(JointVector& q, Leg leg, const Eigen::Vector3d& q_leg) {
  q.segment<3>(kJointsPerLeg * Index(leg)) = q_leg;
}

/// URDF name of a joint of the whole-robot vector, e.g. JointName(5) == "RF_KFE".
std::string JointName(int joint_index);
/// URDF name of joint j (0 HAA, 1 HFE, 2 KFE) of a leg, e.g. "LH_HFE".
std::string JointName(Leg leg, int j);
/// Index in the whole-robot joint vector of a joint name, e.g. JointIndex("RF_KFE") == 5; -1 for
/// a name that is not a leg joint's.
int JointIndex(const std::string& joint_name);

/// Outcome of a leg inverse-kinematics query. `q` is meaningful when ok(); for
/// kOutsideJointBounds it holds the exact (unclamped) solution that violates the bounds.
struct IkResult {
  enum class Status { kOk, kOutOfReach, kOutsideJointBounds };
  Status status = Status::kOutOfReach;
  Eigen::Vector3d q = Eigen::Vector3d::Zero();  ///< (HAA, HFE, KFE) [rad]
  std::string reason;                           ///< empty when ok()
  bool ok() const { return status == Status::kOk; }
};

/// One joint of the URDF. A loaded model has the 12 leg joints (revolute or continuous, named by
/// JointName) and any number of fixed joints.
struct RobotJoint {
  enum class Type { kRevolute, kContinuous, kFixed };
  std::string name;
  Type type = Type::kFixed;
  std::string parent_link;
  std::string child_link;
  /// The joint frame in the parent link frame: the child link's frame at zero joint position.
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();  ///< unit rotation axis in the joint frame; zero when fixed
  double lower_limit = 0.0;  ///< position limits [rad] of a revolute joint; -inf, +inf when continuous
  double upper_limit = 0.0;
};

/// One link of the URDF with its inertial data.
struct RobotLink {
  std::string name;
  std::optional<Leg> leg;                             ///< nullopt for links rigid with the trunk
  double mass = 0.0;                                  ///< [kg]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      ///< centre of mass in the link frame [m]
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  ///< about the CoM, in link axes [kg m^2]
};

/// A collision primitive of a link. Cylinders have their axis along the shape frame's z.
struct CollisionShape {
  enum class Kind { kBox, kCylinder, kSphere };
  std::string name;        ///< URDF collision name (may be empty)
  std::string link;        ///< owning link name
  int link_index = -1;     ///< index into RobotModel::Links() and RobotModel::LinkPoses()
  std::optional<Leg> leg;  ///< nullopt for trunk shapes
  Kind kind = Kind::kBox;
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();           ///< full extents along x, y, z [m] (box)
  double radius = 0.0;                                          ///< [m] (cylinder, sphere)
  double length = 0.0;                                          ///< [m] along z (cylinder)
  Eigen::Isometry3d pose_link = Eigen::Isometry3d::Identity();  ///< shape frame in the link frame
};

/// How far from a straight leg a planned stance stays (a straight leg is at a singularity). The
/// values are the robot file's (kinematic_margins in anymal_b.yaml); RobotModel::Load sets them.
struct KinematicMargins {
  double max_stance_hip_distance_m = 0.0;    ///< stance foot to its hip (HAA origin) [m]
  double max_lift_off_hip_distance_m = 0.0;  ///< the foot about to lift, trunk at the step pose [m]
  double min_knee_bend_rad = 0.0;            ///< least |KFE| [rad]
};

/// Immutable robot model. Every query is const, allocation-free (except the reasons of failed
/// IK queries and the LinkPoses overload that returns a vector) and safe to share across threads.
/// Caller-owned scratch of RobotModel::CenterOfMass(q, data): the body poses of the last query,
/// kept per leg, so a caller that moves one leg at a time (a foothold search) recomputes that
/// leg only. One per thread.
struct BodyPoseData {
  JointVector q = JointVector::Zero();
  std::array<Eigen::Isometry3d, 1 + kNumJoints> poses;
  bool valid = false;
};

class RobotModel {
 public:
  /// Loads the URDF and the planning parameters. The URDF is read here only: the simulator and
  /// the tools build from the model. Throws rbcp::InputError naming the file and the problem:
  /// unreadable or malformed file, missing or unexpected joint, joint axis or origin rotation
  /// the leg model does not support, revolute joint limits not ordered, a missing foot link,
  /// unsupported or empty collision geometry, missing/unknown/invalid YAML key, a link without
  /// a positive, finite mass or a positive definite inertia. Every link needs both (the shipped
  /// URDF gives every link an <inertial>): a link may be a rigid body of its own, as each foot is
  /// in the simulator, and a rigid body without mass or rotational inertia has no dynamics.
  static RobotModel Load(const std::string& urdf_path, const std::string& yaml_path);
  /// Loads config_dir/robots/anymal_b.urdf and config_dir/robots/anymal_b.yaml.
  static RobotModel LoadDefault(const std::string& config_dir);

  // ---- Leg kinematics -------------------------------------------------------------------------

  /// Foot contact point in the base frame [m] for the leg joints q_leg (HAA, HFE, KFE).
  Eigen::Vector3d FootPosition(Leg leg, const Eigen::Vector3d& q_leg) const;
  /// d(FootPosition)/d(q_leg), column j for joint j [m/rad].
  Eigen::Matrix3d FootJacobian(Leg leg, const Eigen::Vector3d& q_leg) const;
  /// Both of the above in one pass.
  void FootPositionAndJacobian(Leg leg, const Eigen::Vector3d& q_leg, Eigen::Vector3d* p_base,
                               Eigen::Matrix3d* jacobian) const;
  /// Contact points of the four feet in the base frame, LF, RF, LH, RH [m].
  std::array<Eigen::Vector3d, kNumLegs> FootPositions(const JointVector& q) const;

  /// Analytic inverse kinematics: joints that put the leg's foot contact point at p_base (base
  /// frame [m]), knees in the X configuration (fore KFE < 0, hind KFE > 0 within the bounds).
  /// Of the two HAA solutions the one with the foot below the hip (negative z in the HIP frame,
  /// i.e. the frame after HAA) is preferred; the other is returned only when the preferred one
  /// violates the planning bounds.
  /// kOutOfReach: target inside the HAA offset cylinder, beyond the stretched leg or nearer to
  /// the HFE axis than the folded leg allows. kOutsideJointBounds: a solution exists but a joint
  /// leaves the planning bounds (by more than 1e-9 rad); the reason names joint, value, bounds.
  IkResult SolveLegIk(Leg leg, const Eigen::Vector3d& p_base) const;

  /// Static joint torques [N m] the leg actuators must apply to hold the leg still against the
  /// force f [N] (base axes) exerted BY the ground ON the foot contact point, leg weight ignored:
  /// tau = -J^T f. A positive component acts in the positive joint direction.
  Eigen::Vector3d StaticTorques(Leg leg, const Eigen::Vector3d& q_leg, const Eigen::Vector3d& foot_force_base) const;

  /// Joint torques [N m] that hold the leg's own links still against gravity with the trunk held
  /// fixed: gravity_base is the gravity acceleration in base axes [m/s^2], e.g.
  /// R_WB^T (0, 0, -9.81). A positive component acts in the positive joint direction.
  Eigen::Vector3d LegGravityTorques(Leg leg, const Eigen::Vector3d& q_leg, const Eigen::Vector3d& gravity_base) const;
  /// The leg's joint-space inertia [kg m^2] with the trunk held fixed (every link's mass and
  /// rotational inertia): M q_dd are the torques that accelerate the leg's joints by q_dd from rest.
  Eigen::Matrix3d LegMassMatrix(Leg leg, const Eigen::Vector3d& q_leg) const;

  // ---- Whole body ------------------------------------------------------------------------------

  /// Sum of all link masses [kg].
  double TotalMass() const { return total_mass_; }
  /// Whole-body centre of mass in the base frame [m].
  Eigen::Vector3d CenterOfMass(const JointVector& q) const;
  /// The same, with the body poses of the legs whose joints equal data's taken from it; leaves
  /// q's poses in *data.
  Eigen::Vector3d CenterOfMass(const JointVector& q, BodyPoseData* data) const;

  /// All URDF links: base first, then each leg (LF, RF, LH, RH) from hip to foot.
  const std::vector<RobotLink>& Links() const { return links_; }
  /// Index into Links() of a link name, or -1 when the model has no such link.
  int LinkIndex(const std::string& name) const;
  /// Pose of every link (same order as Links()) in the base frame. `poses_base` is resized to
  /// Links().size(); reusing the vector avoids allocation.
  void LinkPoses(const JointVector& q, std::vector<Eigen::Isometry3d>* poses_base) const;
  std::vector<Eigen::Isometry3d> LinkPoses(const JointVector& q) const;
  /// Sets the poses of one leg's links in `poses_base` (a LinkPoses() vector) to those of the leg's
  /// joints q_leg (HAA, HFE, KFE), leaving the other links as they are: the links of a
  /// configuration that differs from the vector's only in that leg, at a quarter of the cost.
  void SetLegLinkPoses(Leg leg, const Eigen::Vector3d& q_leg, std::vector<Eigen::Isometry3d>* poses_base) const;
  /// Every joint of the URDF, fixed ones included, breadth first from the base link, each link's
  /// child joints in name order: a joint never precedes the joint that places its parent link.
  const std::vector<RobotJoint>& Joints() const { return joints_; }
  /// Collision primitives of all links, in link order then URDF order.
  const std::vector<CollisionShape>& CollisionShapes() const { return collision_shapes_; }

  // ---- Planning parameters ---------------------------------------------------------------------

  /// Reference standing configuration [rad].
  const JointVector& ReferenceConfiguration() const { return q_reference_; }
  /// Planning joint bounds [rad].
  const JointVector& JointLowerBounds() const { return q_lower_; }
  const JointVector& JointUpperBounds() const { return q_upper_; }
  Eigen::Vector3d LegLowerBounds(Leg leg) const { return LegJoints(q_lower_, leg); }
  Eigen::Vector3d LegUpperBounds(Leg leg) const { return LegJoints(q_upper_, leg); }
  /// True when every joint of q_leg lies within the planning bounds (inclusive, 1e-9 rad slack).
  bool WithinJointBounds(Leg leg, const Eigen::Vector3d& q_leg) const;
  /// Height of the base origin above flat ground in the reference configuration [m].
  double NominalBaseHeight() const { return nominal_base_height_; }
  /// Contact point relative to the FOOT frame, in the shank frame [m].
  const Eigen::Vector3d& FootContactOffset() const { return foot_contact_offset_; }
  /// Foot sphere radius [m].
  double FootRadius() const { return foot_radius_; }
  /// Peak joint torque [N m].
  double TorqueLimit() const { return torque_limit_; }
  /// Continuous joint torque [N m].
  double ContinuousTorqueLimit() const { return continuous_torque_limit_; }
  /// Joint speed limit [rad/s].
  double JointVelocityLimit() const { return joint_velocity_limit_; }

  /// Kinematic margins of a planned stance (see KinematicMargins).
  const KinematicMargins& Margins() const { return margins_; }
  /// The leg within the margins with its foot at p_base (base frame) and joints q_leg: the foot
  /// at most `max_hip_distance` from the hip (HAA origin), the knee bent at least min_knee_bend.
  bool WithinMargins(Leg leg, const Eigen::Vector3d& p_base, const Eigen::Vector3d& q_leg,
                     double max_hip_distance) const {
    return (p_base - HipPosition(leg)).norm() <= max_hip_distance && KneeBent(q_leg);
  }
  /// The knee of joints q_leg bent at least the margins' min_knee_bend.
  bool KneeBent(const Eigen::Vector3d& q_leg) const { return std::abs(q_leg.z()) >= margins_.min_knee_bend_rad; }
  /// The margins' hip distance of a stance foot, or of the foot about to lift.
  double MaxHipDistance(bool lifting) const {
    return lifting ? margins_.max_lift_off_hip_distance_m : margins_.max_stance_hip_distance_m;
  }

  /// HAA joint origin in the base frame [m].
  const Eigen::Vector3d& HipPosition(Leg leg) const { return legs_[static_cast<std::size_t>(Index(leg))].hip; }
  /// Foot contact point of the reference configuration in the base frame [m].
  const Eigen::Vector3d& ReferenceFootPosition(Leg leg) const {
    return reference_feet_[static_cast<std::size_t>(Index(leg))];
  }

 private:
  RobotModel() = default;

  /// Chain constants of one leg, precomputed at load.
  struct LegChain {
    // Generic transform chain: joint origin (rotation, translation) in the parent frame and the
    // joint axis in the joint frame, for HAA, HFE, KFE.
    std::array<Eigen::Matrix3d, 3> origin_rotation;
    std::array<Eigen::Vector3d, 3> origin_translation;
    std::array<Eigen::Vector3d, 3> axis;
    Eigen::Vector3d contact_in_shank;  ///< foot contact point in the shank (KFE child) frame
    // Analytic IK constants (valid because HAA turns about x and HFE, KFE about y).
    Eigen::Vector3d hip;       ///< HAA origin in base
    double lateral = 0.0;      ///< constant y of the contact point in the hip frame
    Eigen::Vector2d hfe_xz;    ///< HFE origin (x, z) in the hip frame
    Eigen::Vector2d thigh_xz;  ///< KFE origin (x, z) in the thigh frame
    Eigen::Vector2d shank_xz;  ///< contact point (x, z) in the shank frame
    double thigh_length = 0.0;
    double shank_length = 0.0;
    double knee_straight = 0.0;  ///< KFE angle of the stretched leg
    double knee_branch = 0.0;    ///< -1: KFE below knee_straight (fore X), +1: above (hind X)
  };

  /// Rigid bodies moved by the joints: 0 is the trunk, 1 + 3 * leg + j the child of joint j.
  static constexpr int kNumBodies = 1 + kNumJoints;
  /// A leg's joints and bodies in the base frame at q_leg: joint j's origin and axis, and the
  /// mass and centre of mass of the body it turns (its child link and the links fixed to it).
  struct LegBodies {
    std::array<Eigen::Vector3d, kJointsPerLeg> origin;
    std::array<Eigen::Vector3d, kJointsPerLeg> axis;
    std::array<Eigen::Vector3d, kJointsPerLeg> com;
    std::array<double, kJointsPerLeg> mass{};
    std::array<Eigen::Isometry3d, kJointsPerLeg> pose;  ///< the body's frame
  };
  LegBodies LegBodiesAt(Leg leg, const Eigen::Vector3d& q_leg) const;
  struct LinkPlacement {
    int body = 0;
    Eigen::Isometry3d body_to_link = Eigen::Isometry3d::Identity();
  };
  struct Branch;
  struct Loader;  ///< the steps of Load (robot_model_load.cpp)

  void BodyPoses(const JointVector& q, std::array<Eigen::Isometry3d, kNumBodies>* poses) const;
  /// The mass-weighted mean of the bodies' centres of mass at these poses.
  Eigen::Vector3d CenterOfMassAt(const std::array<Eigen::Isometry3d, kNumBodies>& poses) const;
  /// The poses of the three bodies of `leg` (entries 1 + 3 * leg + j) for its joints q_leg.
  void LegBodyPoses(Leg leg, const Eigen::Vector3d& q_leg, std::array<Eigen::Isometry3d, kNumBodies>* poses) const;
  Branch SolveBranch(Leg leg, double x_hip, double z_hip, double beta) const;
  bool BoundsReason(Leg leg, const Eigen::Vector3d& q_leg, std::string* reason) const;

  std::array<LegChain, kNumLegs> legs_;
  std::vector<RobotJoint> joints_;
  std::vector<RobotLink> links_;
  std::vector<LinkPlacement> placements_;
  std::vector<CollisionShape> collision_shapes_;
  std::array<double, kNumBodies> body_mass_{};
  std::array<Eigen::Vector3d, kNumBodies> body_com_;  ///< lumped CoM in the body frame
  double total_mass_ = 0.0;

  JointVector q_reference_ = JointVector::Zero();
  JointVector q_lower_ = JointVector::Zero();
  JointVector q_upper_ = JointVector::Zero();
  std::array<Eigen::Vector3d, kNumLegs> reference_feet_;
  double nominal_base_height_ = 0.0;
  Eigen::Vector3d foot_contact_offset_ = Eigen::Vector3d::Zero();
  double foot_radius_ = 0.0;
  double torque_limit_ = 0.0;
  double continuous_torque_limit_ = 0.0;
  KinematicMargins margins_;
  double joint_velocity_limit_ = 0.0;
};

}  // namespace rbcp
