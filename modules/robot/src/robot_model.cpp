// Leg kinematics (generic transform chain, analytic Jacobian and inverse) and whole-body queries.

#include "rbcp/robot/robot_model.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "rbcp/core/angle.h"
#include "rbcp/core/error.h"

namespace rbcp {
namespace {

constexpr double kBoundSlack = 1e-9;   // [rad] tolerance of the planning-bound checks
constexpr double kReachSlack = 1e-12;  // [m] tolerance of the reach checks

/// Rotation by angle q [rad] about the unit axis u (Rodrigues).
inline Eigen::Matrix3d AxisRotation(const Eigen::Vector3d& u, double q) {
  const double s = std::sin(q);
  const double c = std::cos(q);
  const double v = 1.0 - c;
  Eigen::Matrix3d R;
  R << c + u.x() * u.x() * v, u.x() * u.y() * v - u.z() * s, u.x() * u.z() * v + u.y() * s,  //
      u.y() * u.x() * v + u.z() * s, c + u.y() * u.y() * v, u.y() * u.z() * v - u.x() * s,   //
      u.z() * u.x() * v - u.y() * s, u.z() * u.y() * v + u.x() * s, c + u.z() * u.z() * v;
  return R;
}

std::string Format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string Format(const char* fmt, ...) {
  char buf[256];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof(buf), fmt, args);
  va_end(args);
  return buf;
}

}  // namespace

/// One of the two HAA solutions, solved through the planar HFE-KFE problem.
struct RobotModel::Branch {
  bool reachable = false;
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  std::string reason;
};

void RobotModel::FootPositionAndJacobian(Leg leg, const Eigen::Vector3d& q_leg, Eigen::Vector3d* p_base,
                                         Eigen::Matrix3d* jacobian) const {
  const LegChain& c = legs_[static_cast<std::size_t>(Index(leg))];
  // Joint j: origin p_j and axis z_j in base; M_j is the orientation of its child link.
  const Eigen::Vector3d& p0 = c.origin_translation[0];
  const Eigen::Matrix3d M0 = c.origin_rotation[0] * AxisRotation(c.axis[0], q_leg[0]);
  const Eigen::Vector3d p1 = p0 + M0 * c.origin_translation[1];
  const Eigen::Matrix3d F1 = M0 * c.origin_rotation[1];
  const Eigen::Matrix3d M1 = F1 * AxisRotation(c.axis[1], q_leg[1]);
  const Eigen::Vector3d p2 = p1 + M1 * c.origin_translation[2];
  const Eigen::Matrix3d F2 = M1 * c.origin_rotation[2];
  const Eigen::Matrix3d M2 = F2 * AxisRotation(c.axis[2], q_leg[2]);
  const Eigen::Vector3d foot = p2 + M2 * c.contact_in_shank;
  if (p_base) *p_base = foot;
  if (jacobian) {
    jacobian->col(0) = (c.origin_rotation[0] * c.axis[0]).cross(foot - p0);
    jacobian->col(1) = (F1 * c.axis[1]).cross(foot - p1);
    jacobian->col(2) = (F2 * c.axis[2]).cross(foot - p2);
  }
}

Eigen::Vector3d RobotModel::FootPosition(Leg leg, const Eigen::Vector3d& q_leg) const {
  Eigen::Vector3d p;
  FootPositionAndJacobian(leg, q_leg, &p, nullptr);
  return p;
}

Eigen::Matrix3d RobotModel::FootJacobian(Leg leg, const Eigen::Vector3d& q_leg) const {
  Eigen::Matrix3d J;
  FootPositionAndJacobian(leg, q_leg, nullptr, &J);
  return J;
}

std::array<Eigen::Vector3d, kNumLegs> RobotModel::FootPositions(const JointVector& q) const {
  std::array<Eigen::Vector3d, kNumLegs> feet;
  for (Leg leg : kAllLegs) feet[static_cast<std::size_t>(Index(leg))] = FootPosition(leg, LegJoints(q, leg));
  return feet;
}

Eigen::Vector3d RobotModel::StaticTorques(Leg leg, const Eigen::Vector3d& q_leg,
                                          const Eigen::Vector3d& foot_force_base) const {
  return -FootJacobian(leg, q_leg).transpose() * foot_force_base;
}

RobotModel::LegBodies RobotModel::LegBodiesAt(Leg leg, const Eigen::Vector3d& q_leg) const {
  const LegChain& c = legs_[static_cast<std::size_t>(Index(leg))];
  LegBodies b;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int j = 0; j < kJointsPerLeg; ++j) {
    const std::size_t k = static_cast<std::size_t>(j);
    p += R * c.origin_translation[k];
    const Eigen::Matrix3d F = R * c.origin_rotation[k];
    b.origin[k] = p;
    b.axis[k] = F * c.axis[k];
    R = F * AxisRotation(c.axis[k], q_leg[j]);
    b.pose[k].linear() = R;
    b.pose[k].translation() = p;
    const std::size_t body = static_cast<std::size_t>(1 + kJointsPerLeg * Index(leg) + j);
    b.mass[k] = body_mass_[body];
    b.com[k] = p + R * body_com_[body];
  }
  return b;
}

Eigen::Vector3d RobotModel::LegGravityTorques(Leg leg, const Eigen::Vector3d& q_leg,
                                              const Eigen::Vector3d& gravity_base) const {
  const LegBodies b = LegBodiesAt(leg, q_leg);
  // The actuator of joint j cancels the gravity moment of every body it carries about its axis.
  Eigen::Vector3d tau = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < b.axis.size(); ++j) {
    for (std::size_t k = j; k < b.axis.size(); ++k) {
      const Eigen::Vector3d lever = b.mass[k] * (b.com[k] - b.origin[j]);
      tau[static_cast<int>(j)] -= b.axis[j].dot(lever.cross(gravity_base));
    }
  }
  return tau;
}

Eigen::Matrix3d RobotModel::LegMassMatrix(Leg leg, const Eigen::Vector3d& q_leg) const {
  const LegBodies b = LegBodiesAt(leg, q_leg);
  // M = sum over the leg's links of m J_v^T J_v + J_w^T I J_w, where joint j moves a link on
  // body k >= j: its CoM at a_j x (c - o_j) and its frame at a_j per unit rate.
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  const int first_body = 1 + kJointsPerLeg * Index(leg);
  for (std::size_t i = 0; i < placements_.size(); ++i) {
    const int k = placements_[i].body - first_body;
    if (k < 0 || k >= kJointsPerLeg) continue;
    const RobotLink& link = links_[i];
    const Eigen::Isometry3d pose = b.pose[static_cast<std::size_t>(k)] * placements_[i].body_to_link;
    const Eigen::Vector3d c = pose * link.com;
    Eigen::Matrix3d Jv = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d Jw = Eigen::Matrix3d::Zero();
    for (int j = 0; j <= k; ++j) {
      const std::size_t jj = static_cast<std::size_t>(j);
      Jv.col(j) = b.axis[jj].cross(c - b.origin[jj]);
      Jw.col(j) = b.axis[jj];
    }
    const Eigen::Matrix3d I = pose.linear() * link.inertia * pose.linear().transpose();
    M += link.mass * Jv.transpose() * Jv + Jw.transpose() * I * Jw;
  }
  return M;
}

bool RobotModel::WithinJointBounds(Leg leg, const Eigen::Vector3d& q_leg) const {
  const int base = kJointsPerLeg * Index(leg);
  for (int j = 0; j < kJointsPerLeg; ++j) {
    if (!(q_leg[j] >= q_lower_[base + j] - kBoundSlack && q_leg[j] <= q_upper_[base + j] + kBoundSlack)) return false;
  }
  return true;
}

bool RobotModel::BoundsReason(Leg leg, const Eigen::Vector3d& q_leg, std::string* reason) const {
  const int base = kJointsPerLeg * Index(leg);
  for (int j = 0; j < kJointsPerLeg; ++j) {
    const double lo = q_lower_[base + j];
    const double hi = q_upper_[base + j];
    if (!(q_leg[j] >= lo - kBoundSlack && q_leg[j] <= hi + kBoundSlack)) {
      *reason =
          JointName(leg, j) + Format(" = %.4f rad is outside the planning bounds [%.4f, %.4f] rad", q_leg[j], lo, hi);
      return true;
    }
  }
  return false;
}

RobotModel::Branch RobotModel::SolveBranch(Leg leg, double x_hip, double z_hip, double beta) const {
  const LegChain& c = legs_[static_cast<std::size_t>(Index(leg))];
  Branch out;
  // HAA turns the hip-frame pair (lateral, z_hip) onto the target's (y, z) about the HAA axis.
  out.q[0] = WrapAngle(beta - std::atan2(z_hip, c.lateral));

  // Planar problem in the hip x-z plane: t = R(q1) (a + R(q2) b), R(q) turning (x, z) by -q.
  const Eigen::Vector2d t(x_hip - c.hfe_xz.x(), z_hip - c.hfe_xz.y());
  const double d2 = t.squaredNorm();
  const double d = std::sqrt(d2);
  const double la = c.thigh_length;
  const double lb = c.shank_length;
  if (d > la + lb + kReachSlack) {
    out.reason = Format("%s: target is %.4f m from the HFE axis in the leg plane, beyond the stretched leg (%.4f m)",
                        LegName(leg).data(), d, la + lb);
    return out;
  }
  if (d < std::abs(la - lb) - kReachSlack) {
    out.reason = Format(
        "%s: target is %.4f m from the HFE axis in the leg plane, nearer than the folded leg allows "
        "(%.4f m)",
        LegName(leg).data(), d, std::abs(la - lb));
    return out;
  }
  const double cos_knee = std::clamp((d2 - la * la - lb * lb) / (2.0 * la * lb), -1.0, 1.0);
  out.q[2] = WrapAngle(c.knee_straight + c.knee_branch * std::acos(cos_knee));
  const double s2 = std::sin(out.q[2]);
  const double c2 = std::cos(out.q[2]);
  const Eigen::Vector2d& b = c.shank_xz;
  const Eigen::Vector2d v = c.thigh_xz + Eigen::Vector2d(c2 * b.x() + s2 * b.y(), -s2 * b.x() + c2 * b.y());
  out.q[1] = WrapAngle(std::atan2(v.y(), v.x()) - std::atan2(t.y(), t.x()));
  out.reachable = true;
  return out;
}

IkResult RobotModel::SolveLegIk(Leg leg, const Eigen::Vector3d& p_base) const {
  const LegChain& c = legs_[static_cast<std::size_t>(Index(leg))];
  IkResult result;
  if (!p_base.allFinite()) {
    result.status = IkResult::Status::kOutOfReach;
    result.reason = std::string(LegName(leg)) + ": target is not finite";
    return result;
  }
  const Eigen::Vector3d r = p_base - c.hip;
  const double rho2 = r.y() * r.y() + r.z() * r.z();
  const double lateral2 = c.lateral * c.lateral;
  if (rho2 < lateral2) {
    result.status = IkResult::Status::kOutOfReach;
    result.reason = Format("%s: target is %.4f m from the HAA axis, inside the %.4f m lateral offset of the leg",
                           LegName(leg).data(), std::sqrt(rho2), std::abs(c.lateral));
    return result;
  }
  const double h = std::sqrt(rho2 - lateral2);
  const double beta = std::atan2(r.z(), r.y());

  Branch down = SolveBranch(leg, r.x(), -h, beta);
  if (down.reachable && WithinJointBounds(leg, down.q)) {
    result.status = IkResult::Status::kOk;
    result.q = down.q;
    return result;
  }
  if (h > 0.0) {
    Branch up = SolveBranch(leg, r.x(), h, beta);
    if (up.reachable && WithinJointBounds(leg, up.q)) {
      result.status = IkResult::Status::kOk;
      result.q = up.q;
      return result;
    }
    if (!down.reachable && up.reachable) down = std::move(up);
  }
  if (!down.reachable) {
    result.status = IkResult::Status::kOutOfReach;
    result.reason = std::move(down.reason);
    return result;
  }
  result.status = IkResult::Status::kOutsideJointBounds;
  result.q = down.q;
  BoundsReason(leg, down.q, &result.reason);
  return result;
}

void RobotModel::LegBodyPoses(Leg leg, const Eigen::Vector3d& q_leg,
                              std::array<Eigen::Isometry3d, kNumBodies>* poses) const {
  const LegChain& c = legs_[static_cast<std::size_t>(Index(leg))];
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int j = 0; j < kJointsPerLeg; ++j) {
    const std::size_t k = static_cast<std::size_t>(j);
    p += R * c.origin_translation[k];
    R = R * c.origin_rotation[k] * AxisRotation(c.axis[k], q_leg[j]);
    Eigen::Isometry3d& T = (*poses)[static_cast<std::size_t>(1 + kJointsPerLeg * Index(leg) + j)];
    T.linear() = R;
    T.translation() = p;
    T.makeAffine();
  }
}

void RobotModel::BodyPoses(const JointVector& q, std::array<Eigen::Isometry3d, kNumBodies>* poses) const {
  (*poses)[0].setIdentity();
  for (Leg leg : kAllLegs) LegBodyPoses(leg, q.segment<kJointsPerLeg>(kJointsPerLeg * Index(leg)), poses);
}

Eigen::Vector3d RobotModel::CenterOfMass(const JointVector& q) const {
  std::array<Eigen::Isometry3d, kNumBodies> poses;
  BodyPoses(q, &poses);
  return CenterOfMassAt(poses);
}

Eigen::Vector3d RobotModel::CenterOfMass(const JointVector& q, BodyPoseData* data) const {
  static_assert(std::tuple_size<decltype(data->poses)>::value == kNumBodies, "BodyPoseData holds every body");
  if (!data->valid) data->poses[0].setIdentity();
  for (Leg leg : kAllLegs) {
    const auto q_leg = q.segment<kJointsPerLeg>(kJointsPerLeg * Index(leg));
    if (!data->valid || q_leg != data->q.segment<kJointsPerLeg>(kJointsPerLeg * Index(leg))) {
      LegBodyPoses(leg, q_leg, &data->poses);
    }
  }
  data->q = q;
  data->valid = true;
  return CenterOfMassAt(data->poses);
}

Eigen::Vector3d RobotModel::CenterOfMassAt(const std::array<Eigen::Isometry3d, kNumBodies>& poses) const {
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  for (std::size_t b = 0; b < poses.size(); ++b) weighted += body_mass_[b] * (poses[b] * body_com_[b]);
  return weighted / total_mass_;
}

int RobotModel::LinkIndex(const std::string& name) const {
  for (std::size_t i = 0; i < links_.size(); ++i) {
    if (links_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

void RobotModel::LinkPoses(const JointVector& q, std::vector<Eigen::Isometry3d>* poses_base) const {
  std::array<Eigen::Isometry3d, kNumBodies> bodies;
  BodyPoses(q, &bodies);
  poses_base->resize(placements_.size());
  for (std::size_t i = 0; i < placements_.size(); ++i) {
    (*poses_base)[i] = bodies[static_cast<std::size_t>(placements_[i].body)] * placements_[i].body_to_link;
  }
}

void RobotModel::SetLegLinkPoses(Leg leg, const Eigen::Vector3d& q_leg,
                                 std::vector<Eigen::Isometry3d>* poses_base) const {
  RBCP_CHECK(poses_base->size() == placements_.size(), "SetLegLinkPoses needs a LinkPoses() vector");
  std::array<Eigen::Isometry3d, kNumBodies> bodies;
  LegBodyPoses(leg, q_leg, &bodies);
  const int first = 1 + kJointsPerLeg * Index(leg);
  for (std::size_t i = 0; i < placements_.size(); ++i) {
    const int b = placements_[i].body;
    if (b >= first && b < first + kJointsPerLeg) {
      (*poses_base)[i] = bodies[static_cast<std::size_t>(b)] * placements_[i].body_to_link;
    }
  }
}

std::vector<Eigen::Isometry3d> RobotModel::LinkPoses(const JointVector& q) const {
  std::vector<Eigen::Isometry3d> poses;
  LinkPoses(q, &poses);
  return poses;
}

}  // namespace rbcp
