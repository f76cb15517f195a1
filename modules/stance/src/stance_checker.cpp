#include "rbcp/stance/stance_checker.h"

#include <cmath>
#include <limits>
#include <string_view>

#include "rbcp/core/angle.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/stance_torques.h"
#include "rbcp/equilibrium/support_polygon.h"

namespace rbcp {
namespace {

StanceVerdict Fail(StanceCheck check, std::string detail, std::optional<Leg> leg = std::nullopt) {
  StanceVerdict v;
  v.check = check;
  v.detail = std::move(detail);
  v.leg = leg;
  return v;
}

StanceVerdict InPhase(StanceVerdict v, StepPhase phase) {
  v.phase = phase;
  return v;
}

/// The leg a robot shape belongs to ("LF_THIGH" -> LF), nullopt for the trunk's.
std::optional<Leg> ShapeLeg(const std::string& shape) {
  return shape.size() >= 2 ? LegFromName(std::string_view(shape).substr(0, 2)) : std::nullopt;
}

}  // namespace

std::vector<Eigen::Vector3d> FeetPositions(const FootContacts& feet, int skip) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < kNumLegs; ++i) {
    if (i != skip) out.push_back(feet[static_cast<std::size_t>(i)].position);
  }
  return out;
}

const char* ToString(StanceCheck check) {
  switch (check) {
    case StanceCheck::kOk: return "ok";
    case StanceCheck::kReach: return "reach";
    case StanceCheck::kCollision: return "collision";
    case StanceCheck::kSelfCollision: return "self_collision";
    case StanceCheck::kSupport: return "support";
    case StanceCheck::kBalance: return "balance";
    case StanceCheck::kTorque: return "torque";
    case StanceCheck::kSwingTerrain: return "swing_terrain";
    case StanceCheck::kSwingBody: return "swing_body";
  }
  return "?";
}

const char* ToString(StepPhase phase) {
  switch (phase) {
    case StepPhase::kShift: return "shift";
    case StepPhase::kLiftOff: return "lift_off";
    case StepPhase::kSwing: return "swing";
    case StepPhase::kTouchDown: return "touch_down";
  }
  return "?";
}

std::string StanceVerdict::Describe() const {
  if (ok()) return "ok";
  return std::string(ToString(phase)) + ": " + ToString(check) + ": " + detail;
}

StanceChecker::StanceChecker(const RobotModel& robot, const StanceRules& rules) : robot_(&robot), rules_(rules) {
  rules_.config.Validate();
  if (!(std::isfinite(rules_.friction) && rules_.friction > 0.0)) {
    throw InputError("StanceChecker: expected a positive friction coefficient, got " + FixedNumber(rules_.friction));
  }
}

StanceChecker::~StanceChecker() = default;
StanceChecker::StanceChecker(StanceChecker&&) noexcept = default;
StanceChecker& StanceChecker::operator=(StanceChecker&&) noexcept = default;

void StanceChecker::SetTerrain(const TriangleMesh* terrain) {
  terrain_.reset();
  exact_.reset();
  heights_.reset();
  if (terrain == nullptr || terrain->triangles.empty()) return;
  CollisionOptions options;
  options.measure_penetration = false;
  exact_ = std::make_unique<RobotTerrainCollision>(*robot_, *terrain, options);
  options.thigh_margin = Config().thigh_clearance_m;
  options.trunk_margin = Config().trunk_clearance_m;
  terrain_ = std::make_unique<RobotTerrainCollision>(*robot_, *terrain, options);
  heights_ = std::make_unique<TerrainHeightMap>(*terrain);
}

double StanceChecker::TorqueCeiling() const { return Config().torque_limit_fraction * robot_->ContinuousTorqueLimit(); }

const RobotTerrainCollision& StanceChecker::TerrainCollision() const {
  RBCP_CHECK(terrain_ != nullptr, "StanceChecker::TerrainCollision without a terrain");
  return *terrain_;
}

const RobotTerrainCollision& StanceChecker::ExactCollision() const {
  RBCP_CHECK(exact_ != nullptr, "StanceChecker::ExactCollision without a terrain");
  return *exact_;
}

std::optional<JointVector> StanceChecker::SolveStance(const Eigen::Isometry3d& base_W, const FootContacts& feet,
                                                      int lifting) const {
  const Eigen::Isometry3d T_BW = base_W.inverse();
  JointVector q = JointVector::Zero();
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d p_B = T_BW * feet[static_cast<std::size_t>(Index(leg))].position;
    const IkResult ik = robot_->SolveLegIk(leg, p_B);
    if (!ik.ok() || !robot_->WithinMargins(leg, p_B, ik.q, robot_->MaxHipDistance(Index(leg) == lifting))) {
      return std::nullopt;
    }
    SetLegJoints(q, leg, ik.q);
  }
  return q;
}

StanceVerdict StanceChecker::Support(const FootContacts& feet, int skip, const Eigen::Vector3d& com_W) const {
  const double margin = SupportPolygonMargin(FeetPositions(feet, skip), com_W);
  if (margin >= Config().support_margin_m) return {};
  return Fail(StanceCheck::kSupport, "CoM " + FixedNumber(margin, 3) + " m inside the support polygon of " +
                                         std::to_string(skip < 0 ? 4 : 3) + " feet, expected at least " +
                                         FixedNumber(Config().support_margin_m, 3) + " m");
}

StanceVerdict StanceChecker::Torques(const Eigen::Isometry3d& base_W, const JointVector& q, const FootContacts& feet,
                                     int skip, const Eigen::Vector3d& com_W, double* max_abs_Nm) const {
  return Torques(base_W, q, feet, skip, com_W, Eigen::Vector3d::Zero(), max_abs_Nm);
}

StanceVerdict StanceChecker::Torques(const Eigen::Isometry3d& base_W, const JointVector& q, const FootContacts& feet,
                                     int skip, const Eigen::Vector3d& com_W, const Eigen::Vector3d& com_acceleration_W,
                                     double* max_abs_Nm) const {
  ForceDistributionParams params;
  params.friction = rules_.friction;
  params.min_normal_force_N = Config().min_normal_force_N;
  const StanceTorques t =
      ComputeStanceTorques(*robot_, base_W, q, StanceFeet(feet, skip), com_W, params, com_acceleration_W);
  if (max_abs_Nm != nullptr) *max_abs_Nm = t.balanced ? t.max_abs_Nm : std::numeric_limits<double>::infinity();
  if (!t.balanced) return Fail(StanceCheck::kBalance, "the feet's friction cones cannot hold the weight");
  if (t.max_abs_Nm > TorqueCeiling()) {
    return Fail(StanceCheck::kTorque,
                JointName(t.worst_joint) + (com_acceleration_W.isZero() ? " static torque " : " torque ") + FixedNumber(t.max_abs_Nm, 1) + " N m, above " +
                    FixedNumber(TorqueCeiling(), 1) + " N m",
                static_cast<Leg>(t.worst_joint / kJointsPerLeg));
  }
  return {};
}

StanceVerdict StanceChecker::LiftOffCollision(const Eigen::Isometry3d& base_W, const JointVector& q, Leg lifting) const {
  CollisionReport hit = TerrainCollision().CheckTrunk(base_W);
  for (Leg leg : kAllLegs) {
    if (hit.collision) break;
    const RobotTerrainCollision& c = leg == lifting ? ExactCollision() : TerrainCollision();
    hit = c.CheckLeg(leg, base_W, LegJoints(q, leg), true);
  }
  if (hit.collision) return Fail(StanceCheck::kCollision, hit.first_shape + " on the terrain", ShapeLeg(hit.first_shape));
  const CollisionReport self = ExactCollision().CheckSelf(q);
  if (self.collision) {
    return Fail(StanceCheck::kSelfCollision, self.first_shape + " on " + self.obstacle, ShapeLeg(self.first_shape));
  }
  return {};
}

SwingTrajectory StanceChecker::PlanSwing(Leg leg, const Eigen::Vector3d& from_W, const Eigen::Vector3d& to_W,
                                         const Eigen::Isometry3d& base_W, const JointVector& q,
                                         SwingSearch search) const {
  if (!HasTerrain()) return SwingTrajectory::Plan(from_W, to_W, nullptr, robot_->FootRadius(), Config().swing);
  const Eigen::Isometry3d T_BW = base_W.inverse();
  // The base holds its pose during the swing: the leg must clear the terrain from there. The
  // foot itself is kept clear by the path's terrain check (it starts and ends on the ground).
  const SwingTrajectory::LegCheck leg_clear = [&](const Eigen::Vector3d& foot_W) {
    // A foot the leg cannot reach within its joint bounds would press a joint into its stop.
    const IkResult ik = robot_->SolveLegIk(leg, T_BW * foot_W);
    return ik.ok() && !terrain_->CheckLeg(leg, base_W, ik.q, true).collision;
  };
  // The leg also keeps clear of the trunk and the other legs: a hind leg stepping down from a
  // tread close below its hip, lifted straight up, folds its thigh against the trunk and stalls
  // the hip flexion at its torque limit. Checked with the exact shapes, for the swinging leg's
  // pairs only: the rest of q is the lift-off stance, checked whole before the swing.
  const SwingTrajectory::LegCheck clear_of_body = [&](const Eigen::Vector3d& foot_W) {
    const IkResult ik = robot_->SolveLegIk(leg, T_BW * foot_W);
    if (!ik.ok()) return false;
    JointVector q_swing = q;
    SetLegJoints(q_swing, leg, ik.q);
    return !exact_->CheckSelf(q_swing, leg).collision;
  };
  // Towards the body: from the middle of the swing to the base, across the swing direction.
  const Eigen::Vector2d across = (to_W - from_W).head<2>();
  Eigen::Vector2d inward = (base_W.translation() - 0.5 * (to_W + from_W)).head<2>();
  if (across.norm() > 1e-6) inward -= inward.dot(across.normalized()) * across.normalized();
  return SwingTrajectory::Plan(from_W, to_W, heights_.get(), robot_->FootRadius(), Config().swing, leg_clear, inward,
                               clear_of_body, search);
}

StanceVerdict StanceChecker::SwingClearance(const SwingTrajectory& swing, Leg leg) const {
  if (!swing.TerrainClear()) {
    return Fail(StanceCheck::kSwingTerrain,
                std::string(LegName(leg)) + "'s foot cannot keep " + FixedNumber(Config().swing.terrain_clearance_m, 3) +
                    " m above the terrain along its path",
                leg);
  }
  if (swing.LegCollisions() > 0) {
    return Fail(StanceCheck::kSwingTerrain,
                std::string(LegName(leg)) + " touches the terrain or leaves its reach at " +
                    std::to_string(swing.LegCollisions()) + " samples of its best path (apex " +
                    FixedNumber(swing.Apex(), 3) + " m)",
                leg);
  }
  if (Config().swing.body_clearance && swing.PreferredMisses() > 0) {
    return Fail(StanceCheck::kSwingBody,
                std::string(LegName(leg)) + " touches the trunk or another leg at " +
                    std::to_string(swing.PreferredMisses()) + " samples of its best path (apex " +
                    FixedNumber(swing.Apex(), 3) + " m)",
                leg);
  }
  return {};
}

StanceVerdict StanceChecker::CheckShift(const Eigen::Vector3d& from_position, const Eigen::Vector3d& from_rpy,
                                        const Eigen::Isometry3d& to_base, const Eigen::Vector3d& rpy_to,
                                        const FootContacts& feet, int lifting) const {
  const int n = Config().transit_checks;
  for (int k = 1; k <= n; ++k) {
    const double w = static_cast<double>(k) / static_cast<double>(n + 1);
    Eigen::Vector3d rpy = from_rpy + w * (rpy_to - from_rpy);
    rpy.z() = WrapAngle(from_rpy.z() + w * WrapAngle(rpy_to.z() - from_rpy.z()));
    const Eigen::Isometry3d T = PoseFromRpy(from_position + w * (to_base.translation() - from_position), rpy);
    const std::optional<JointVector> q = SolveStance(T, feet, lifting);
    if (!q) return Fail(StanceCheck::kReach, "a foot out of reach while the body moves to the step pose");
    const Eigen::Vector3d com = T * robot_->CenterOfMass(*q);
    if (StanceVerdict v = Support(feet, -1, com); !v.ok()) return v;
    if (HasTerrain()) {
      // The trunk, and the stance legs whose knees move with it, clear of the terrain.
      CollisionReport hit = terrain_->CheckTrunk(T);
      for (Leg leg : kAllLegs) {
        if (hit.collision) break;
        hit = terrain_->CheckLeg(leg, T, LegJoints(*q, leg), true);
      }
      if (hit.collision) {
        return Fail(StanceCheck::kCollision, hit.first_shape + " on the terrain while the body moves",
                    ShapeLeg(hit.first_shape));
      }
    }
    if (StanceVerdict v = Torques(T, *q, feet, -1, com); !v.ok()) return v;
  }
  return {};
}

StanceVerdict StanceChecker::CheckStep(const WholeBodyState& from, const WholeBodyState& to) const {
  RBCP_CHECK(to.moving_leg >= 0 && to.moving_leg < kNumLegs, "a step has a moving leg");
  const int j = to.moving_leg;
  const Leg leg = static_cast<Leg>(j);
  const Eigen::Isometry3d base = BasePose(to);
  if (StanceVerdict v = CheckShift(from.base_position, from.base_rpy, base, to.base_rpy, from.feet, j); !v.ok()) {
    return InPhase(std::move(v), StepPhase::kShift);
  }
  // Lift-off: the old feet at the step's base pose.
  const std::optional<JointVector> q_pre = SolveStance(base, from.feet, j);
  if (!q_pre) return InPhase(Fail(StanceCheck::kReach, "a foot out of reach at the step pose"), StepPhase::kLiftOff);
  const Eigen::Vector3d com_pre = base * robot_->CenterOfMass(*q_pre);
  if (HasTerrain()) {
    if (StanceVerdict v = LiftOffCollision(base, *q_pre, leg); !v.ok()) return InPhase(std::move(v), StepPhase::kLiftOff);
  }
  if (StanceVerdict v = Support(from.feet, j, com_pre); !v.ok()) return InPhase(std::move(v), StepPhase::kLiftOff);
  if (StanceVerdict v = Torques(base, *q_pre, from.feet, j, com_pre); !v.ok()) {
    return InPhase(std::move(v), StepPhase::kLiftOff);
  }
  // The swing.
  const std::size_t i = static_cast<std::size_t>(j);
  if (HasTerrain()) {
    const SwingTrajectory swing =
        PlanSwing(leg, from.feet[i].position, to.feet[i].position, base, *q_pre, SwingSearch::kFirstClear);
    if (StanceVerdict v = SwingClearance(swing, leg); !v.ok()) return InPhase(std::move(v), StepPhase::kSwing);
  }
  // Touch-down and reload, at the state's own joints.
  const Eigen::Vector3d com_post = base * robot_->CenterOfMass(to.joints);
  if (StanceVerdict v = Support(from.feet, j, com_post); !v.ok()) return InPhase(std::move(v), StepPhase::kTouchDown);
  if (StanceVerdict v = Torques(base, to.joints, to.feet, j, com_post); !v.ok()) {
    return InPhase(std::move(v), StepPhase::kTouchDown);
  }
  if (StanceVerdict v = Torques(base, to.joints, to.feet, -1, com_post); !v.ok()) {
    return InPhase(std::move(v), StepPhase::kTouchDown);
  }
  return {};
}

}  // namespace rbcp
