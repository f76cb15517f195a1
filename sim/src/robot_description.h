#pragma once
/// The robot as the simulator builds it: rigid bodies joined by joints, regrouped from the links
/// and joints of the robot model (RobotModel::Load reads and checks the URDF).
///
/// Bodies: the floating base ("base" and every link fixed to it), one body per revolute joint
/// (its child link plus the links fixed to it, e.g. the shank with its adapter tube), and each
/// <LEG>_FOOT link as a body of its own, fixed to the shank body, so that the foot sphere has
/// its own collider and its own contact manifold. Merged links have their masses added, their
/// centres of mass averaged and their inertias moved to the common centre of mass with the
/// parallel-axis theorem. Each body's inertia is then diagonalised: the body's inertial frame
/// is its centre of mass with the principal axes (Bullet's btMultiBody takes a diagonal inertia
/// in the link's own frame).
///
/// Order: bodies[0] is the base, bodies[1 + i] the child of joint i of the whole-robot joint
/// vector (LF, RF, LH, RH x HAA, HFE, KFE), bodies[13 + l] the foot of leg l. Every body's
/// parent comes before it, as btMultiBody requires.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/leg.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp::sim {

/// One collision primitive of the model, placed in its body's frame.
struct BodyShape {
  CollisionShape primitive;                                     ///< as the model has it, on its link
  Eigen::Isometry3d pose_body = Eigen::Isometry3d::Identity();  ///< shape frame in the body frame
};

struct RobotBody {
  enum class Joint { kFloating, kRevolute, kFixed };
  std::string name;        ///< the URDF link that starts the body ("base", "LF_HIP", "LF_FOOT", ...)
  std::vector<std::string> links;  ///< URDF links merged into the body, `name` first
  Joint joint = Joint::kFloating;
  std::string joint_name;  ///< URDF joint to the parent ("" for the base; the fixed joint for a foot)
  int parent = -1;         ///< index of the parent body, -1 for the base
  std::optional<Leg> leg;  ///< nullopt for the base
  bool is_foot = false;
  /// The body frame at zero joint position, in the parent body's frame: the URDF joint origin
  /// (chained through merged fixed joints).
  Eigen::Isometry3d parent_to_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  ///< revolute joint axis in the body frame (unit)
  double lower_limit = 0.0;  ///< revolute joint position limits [rad]
  double upper_limit = 0.0;

  double mass = 0.0;  ///< [kg]
  /// Centre of mass and principal axes in the body frame: columns are the principal axes,
  /// a proper rotation, as close to the body axes as the inertia allows.
  Eigen::Isometry3d inertial_frame = Eigen::Isometry3d::Identity();
  Eigen::Vector3d principal_inertia = Eigen::Vector3d::Zero();  ///< about the CoM, principal axes [kg m^2]
  Eigen::Matrix3d inertia_body = Eigen::Matrix3d::Zero();       ///< about the CoM, body axes [kg m^2]

  std::vector<BodyShape> shapes;
};

struct RobotDescription {
  std::vector<RobotBody> bodies;
  double total_mass = 0.0;  ///< [kg]

  static constexpr int kBase = 0;
  static int JointBody(int joint_index) { return 1 + joint_index; }
  static int FootBody(Leg leg) { return 1 + kNumJoints + Index(leg); }
  static constexpr int kNumBodies = 1 + kNumJoints + kNumLegs;

  /// The bodies of a loaded model (whose loading checked everything these bodies need: the leg
  /// joints, the feet fixed to the shanks, a mass and inertia for every link).
  static RobotDescription FromModel(const RobotModel& model);
};

/// Principal axes of a symmetric inertia tensor: `inertia = R diag(principal) R^T` with R a proper
/// rotation whose columns are matched to the nearest coordinate axes (so R is the identity for a
/// diagonal tensor).
void PrincipalAxes(const Eigen::Matrix3d& inertia, Eigen::Matrix3d* rotation, Eigen::Vector3d* principal);

}  // namespace rbcp::sim
