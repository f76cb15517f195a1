#include "stance_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rbcp/core/format.h"
#include "rbcp/core/pose.h"

namespace rbcp::contact_planner_detail {

StanceBase StanceBaseAt(const PlannerContext& ctx, const PathPose& pose, const Eigen::Vector3d& shift, const Feet& feet,
                        int lifting) {
  const BasePoseConfig& bp = ctx.config.base_pose;
  const Eigen::Matrix3d R_yaw = Yaw(pose.yaw);
  Eigen::Vector3d p = pose.p + R_yaw * Eigen::Vector3d(shift.x(), shift.y(), 0.0);
  Eigen::Vector3d rpy(0.0, 0.0, pose.yaw);
  if (bp.follow_feet) {
    // z = a + b x + c y in the heading frame centred at the base.
    Eigen::Matrix<double, kNumLegs, 3> A;
    Eigen::Matrix<double, kNumLegs, 1> z;
    for (int i = 0; i < kNumLegs; ++i) {
      const Eigen::Vector3d d = R_yaw.transpose() * (feet[static_cast<std::size_t>(i)].position - p);
      A.row(i) << 1.0, d.x(), d.y();
      z[i] = feet[static_cast<std::size_t>(i)].position.z();
    }
    const Eigen::Vector3d abc = A.colPivHouseholderQr().solve(z);
    rpy.y() = std::clamp(-bp.pitch_follow * std::atan(abc[1]), -bp.max_pitch_rad, bp.max_pitch_rad);
    rpy.x() = std::clamp(std::atan(abc[2]), -bp.max_roll_rad, bp.max_roll_rad);
    p.z() = abc[0] + ctx.robot.NominalBaseHeight() + bp.height_offset_m + shift.z();
  } else {
    p.z() += shift.z();
  }
  const Eigen::Matrix3d R = RotationFromRpy(rpy);
  p.z() = std::min(p.z(), MarginHeightCeiling(ctx, p, R, feet, lifting));
  StanceBase out;
  out.base_W.linear() = R;
  out.base_W.translation() = p;
  out.rpy = rpy;
  return out;
}

double MarginHeightCeiling(const PlannerContext& ctx, const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                           const Feet& feet, int lifting) {
  double ceiling = std::numeric_limits<double>::infinity();
  for (Leg leg : kAllLegs) {
    const double d = ctx.robot.MaxHipDistance(Index(leg) == lifting) - 1e-3;
    const Eigen::Vector3d hip_offset = R * ctx.robot.HipPosition(leg);
    const Eigen::Vector3d& foot = feet[static_cast<std::size_t>(Index(leg))].position;
    const double h2 = (foot.head<2>() - p.head<2>() - hip_offset.head<2>()).squaredNorm();
    if (h2 >= d * d) return std::numeric_limits<double>::infinity();
    ceiling = std::min(ceiling, foot.z() - hip_offset.z() + std::sqrt(d * d - h2));
  }
  return ceiling;
}

double WorkspaceRatio(const PlannerContext& ctx, Leg leg, const Eigen::Vector3d& p_B) {
  const FootWorkspace& ws = ctx.config.workspace;
  const Eigen::Vector3d d = p_B - ctx.robot.ReferenceFootPosition(leg);
  double r = d.x() >= 0.0 ? d.x() / ws.max_forward_m : -d.x() / ws.max_backward_m;
  const double out = LeftSign(leg) * d.y();
  r = std::max(r, out >= 0.0 ? out / ws.max_outward_m : -out / ws.max_inward_m);
  r = std::max(r, d.z() >= 0.0 ? d.z() / ws.max_up_m : -d.z() / ws.max_down_m);
  const Eigen::Vector3d from_hip = p_B - ctx.robot.HipPosition(leg);
  r = std::max(r, from_hip.head<2>().norm() / ws.max_hip_distance_m);
  // A stance leg short of straight (the kinematic margins).
  r = std::max(r, from_hip.norm() / ctx.robot.Margins().max_stance_hip_distance_m);
  return r;
}

LegKeep KeepLeg(const PlannerContext& ctx, Leg leg, const Eigen::Isometry3d& base_W, const Eigen::Vector3d& foot_W) {
  ++ctx.stats.keep_checks;
  LegKeep keep;
  const Eigen::Vector3d p_B = base_W.inverse() * foot_W;
  keep.stretch = WorkspaceRatio(ctx, leg, p_B);
  if (keep.stretch > 1.0) {
    keep.failure = KeepFailure::kWorkspace;
    return keep;
  }
  const IkResult ik = ctx.robot.SolveLegIk(leg, p_B);
  if (!ik.ok() || !ctx.robot.KneeBent(ik.q)) {
    keep.failure = KeepFailure::kKinematics;
    return keep;
  }
  keep.q = ik.q;
  if (ctx.stance.TerrainCollision().CheckLeg(leg, base_W, ik.q, true).collision) keep.failure = KeepFailure::kCollision;
  return keep;
}

std::optional<JointVector> SolveStance(const PlannerContext& ctx, const Eigen::Isometry3d& base_W, const Feet& feet,
                                       int lifting) {
  if (lifting != kNoMargins) return ctx.stance.SolveStance(base_W, feet, lifting);
  const Eigen::Isometry3d T_BW = base_W.inverse();
  JointVector q = JointVector::Zero();
  for (Leg leg : kAllLegs) {
    const IkResult ik = ctx.robot.SolveLegIk(leg, T_BW * feet[static_cast<std::size_t>(Index(leg))].position);
    if (!ik.ok()) return std::nullopt;
    SetLegJoints(q, leg, ik.q);
  }
  return q;
}

std::vector<ContactPoint> Contacts(const Feet& feet, int skip) {
  std::vector<ContactPoint> out;
  for (int i = 0; i < kNumLegs; ++i) {
    if (i != skip) out.push_back({feet[static_cast<std::size_t>(i)].position, feet[static_cast<std::size_t>(i)].normal});
  }
  return out;
}

}  // namespace rbcp::contact_planner_detail
