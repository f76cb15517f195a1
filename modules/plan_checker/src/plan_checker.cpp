#include "rbcp/plan_checker/plan_checker.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/collision/robot_terrain_collision.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/stance_torques.h"
#include "rbcp/equilibrium/static_equilibrium.h"
#include "rbcp/equilibrium/support_polygon.h"
#include "rbcp/core/angle.h"
#include "rbcp/stance/dynamic_walk.h"
#include "rbcp/stance/stance_checker.h"

namespace rbcp {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Fixed-point text of a number with the given decimals ("0.0200", "-inf").
std::string Num(double value, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << value;
  return os.str();
}

std::string Point(const Eigen::Vector3d& p) {
  return "(" + Num(p.x(), 4) + ", " + Num(p.y(), 4) + ", " + Num(p.z(), 4) + ")";
}

std::string Name(Leg leg) { return std::string(LegName(leg)); }

/// Collects violations: keeps the first `max` and counts them all.
class ViolationSink {
 public:
  ViolationSink(PlanCheckReport* report, int max) : report_(report), max_(max) {}
  void Add(int state, const char* check, std::string detail) {
    ++report_->violation_count;
    if (static_cast<int>(report_->violations.size()) < max_) {
      report_->violations.push_back(PlanViolation{state, check, std::move(detail)});
    }
  }

 private:
  PlanCheckReport* report_;
  int max_;
};

/// A contact surface in its own plane coordinates, for point queries.
class SurfaceGeometry {
 public:
  explicit SurfaceGeometry(const AffordanceSurface& surface) : normal_(surface.normal.normalized()) {
    // Orthonormal in-plane axes with u x v = normal, so counter-clockwise stays counter-clockwise.
    const Eigen::Vector3d helper = std::abs(normal_.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    u_ = normal_.cross(helper).normalized();
    v_ = normal_.cross(u_);
    offset_ = 0.0;
    for (const auto& p : surface.vertices) offset_ += normal_.dot(p);
    if (!surface.vertices.empty()) offset_ /= static_cast<double>(surface.vertices.size());
    double twice_area = 0.0;
    for (const auto& p : surface.vertices) polygon_.emplace_back(u_.dot(p), v_.dot(p));
    for (std::size_t k = 0; k < polygon_.size(); ++k) {
      const auto& a = polygon_[k];
      const auto& b = polygon_[(k + 1) % polygon_.size()];
      twice_area += a.x() * b.y() - b.x() * a.y();
    }
    if (twice_area < 0.0) std::reverse(polygon_.begin(), polygon_.end());
  }

  bool Valid() const { return polygon_.size() >= 3; }
  const Eigen::Vector3d& Normal() const { return normal_; }
  /// Distance of p to the surface plane [m].
  double PlaneDistance(const Eigen::Vector3d& p) const { return std::abs(normal_.dot(p) - offset_); }
  /// Distance of p's projection onto the plane to the polygon [m], 0 inside.
  double PolygonDistance(const Eigen::Vector3d& p) const {
    const Eigen::Vector2d q(u_.dot(p), v_.dot(p));
    bool inside = true;
    double nearest = kInfinity;
    for (std::size_t k = 0; k < polygon_.size(); ++k) {
      const Eigen::Vector2d& a = polygon_[k];
      const Eigen::Vector2d& b = polygon_[(k + 1) % polygon_.size()];
      const Eigen::Vector2d ab = b - a;
      const Eigen::Vector2d aq = q - a;
      if (ab.x() * aq.y() - ab.y() * aq.x() < 0.0) inside = false;
      const double length2 = ab.squaredNorm();
      const double t = length2 > 0.0 ? std::clamp(ab.dot(aq) / length2, 0.0, 1.0) : 0.0;
      nearest = std::min(nearest, (aq - t * ab).norm());
    }
    return inside ? 0.0 : nearest;
  }

 private:
  Eigen::Vector3d normal_;
  Eigen::Vector3d u_;
  Eigen::Vector3d v_;
  double offset_ = 0.0;
  std::vector<Eigen::Vector2d> polygon_;
};

void RequireFinite(const ContactPlan& plan) {
  for (std::size_t i = 0; i < plan.states.size(); ++i) {
    const WholeBodyState& s = plan.states[i];
    const auto fail = [&](const std::string& what) {
      throw InputError("contact plan: state " + std::to_string(i) + ": expected finite numbers, got a non-finite " +
                       what);
    };
    if (!s.base_position.allFinite()) fail("base position");
    if (!s.base_rpy.allFinite()) fail("base rpy");
    if (!s.joints.allFinite()) fail("joint vector");
    for (Leg leg : kAllLegs) {
      const FootContact& foot = s.feet[static_cast<std::size_t>(Index(leg))];
      if (!foot.position.allFinite()) fail(Name(leg) + " foot position");
      if (!foot.normal.allFinite()) fail(Name(leg) + " foot normal");
    }
  }
}

/// Runs the checks of one plan; one instance per CheckPlan call.
class PlanChecker {
 public:
  PlanChecker(const RobotModel& robot, const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
              const PlanCheckConfig& config, PlanCheckReport* report)
      : robot_(robot),
        config_(config),
        report_(report),
        sink_(report, config.max_violations),
        equilibrium_(robot.TotalMass(), config.equilibrium),
        stance_(robot, config.stance) {
    for (const auto& surface : surfaces) surfaces_.emplace_back(surface);
    if (config.check_collision) {
      collision_ = std::make_unique<RobotTerrainCollision>(robot, terrain);
      stance_.SetTerrain(&terrain);
    }
  }

  void Check(const ContactPlan& plan) {
    for (std::size_t k = 0; k < plan.states.size(); ++k) {
      const int i = static_cast<int>(k);
      const WholeBodyState& state = plan.states[k];
      CheckSurfaces(i, state);
      CheckOneLeg(i, state, k > 0 ? &plan.states[k - 1] : nullptr);
      CheckJointBounds(i, state);
      const std::optional<LiftOff> lift_off = k > 0 ? LiftOffOf(plan.states[k - 1], state) : std::nullopt;
      CheckKinematicMargins(i, state, lift_off);
      CheckForwardKinematics(i, state);
      if (collision_) CheckCollision(i, state);
      CheckStabilityAndTorques(i, state);
      if (lift_off) CheckSupportMargin(i, plan.states[k - 1], state, *lift_off);
      if (lift_off) CheckShift(i, plan.states[k - 1], state);
      if (lift_off && collision_ && lift_off->ik.ok()) CheckSwing(i, plan.states[k - 1], state, *lift_off);
    }
    if (const auto bad = TimingProblem(plan)) {
      sink_.Add(0, "timing", *bad);
    } else if (plan.Timed()) {
      CheckWalk(plan);
    }
  }

 private:
  /// The swing of state i at lift-off: the trunk at state i's pose, the swing foot still on its
  /// foothold of state i - 1 (in the base frame), its joints there by inverse kinematics.
  struct LiftOff {
    Leg swing;
    Eigen::Vector3d foot_B;
    IkResult ik;
  };

  /// nullopt when state i names no valid moving leg (reported by "one_leg").
  std::optional<LiftOff> LiftOffOf(const WholeBodyState& previous, const WholeBodyState& state) const {
    if (state.moving_leg < 0 || state.moving_leg >= kNumLegs) return std::nullopt;
    const Leg swing = kAllLegs[static_cast<std::size_t>(state.moving_leg)];
    const Eigen::Vector3d foot_B = BasePose(state).inverse() * previous.feet[static_cast<std::size_t>(Index(swing))].position;
    return LiftOff{swing, foot_B, robot_.SolveLegIk(swing, foot_B)};
  }

  void CheckWalk(const ContactPlan& plan) {
    for (const WholeBodyState& s : plan.states) {
      if (&s != &plan.states.front() && (s.moving_leg < 0 || s.moving_leg >= kNumLegs)) return;  // "one_leg"
    }
    report_->timed = true;
    const WalkingPattern pattern = DynamicWalkPattern(stance_, plan, DynamicWalkAtRest(stance_, plan));
    for (std::size_t i = 1; i < plan.states.size(); ++i) {
      const DynamicStepCheck c = CheckDynamicStep(stance_, plan, pattern, static_cast<int>(i));
      report_->min_zmp_margin_m = std::min(report_->min_zmp_margin_m, c.min_zmp_margin_m);
      report_->max_walk_torque_Nm = std::max(report_->max_walk_torque_Nm, c.max_torque_Nm);
      if (!c.verdict.ok()) report_->walk_violations.push_back({static_cast<int>(i), "walk", c.verdict.Describe()});
    }
  }

  void CheckSurfaces(int i, const WholeBodyState& state) {
    const double tol = config_.surface_tolerance;
    for (Leg leg : kAllLegs) {
      const FootContact& foot = state.feet[static_cast<std::size_t>(Index(leg))];
      bool on_surface = false;
      int nearest = -1;
      double nearest_distance = kInfinity, nearest_plane = 0.0, nearest_polygon = 0.0, nearest_normal = 0.0;
      for (std::size_t s = 0; s < surfaces_.size() && !on_surface; ++s) {
        const SurfaceGeometry& surface = surfaces_[s];
        if (!surface.Valid()) continue;
        const double plane = surface.PlaneDistance(foot.position);
        const double polygon = surface.PolygonDistance(foot.position);
        const double normal = (foot.normal - surface.Normal()).norm();
        if (plane <= tol && polygon <= tol && normal <= config_.normal_tolerance) {
          on_surface = true;
        } else if (std::hypot(plane, polygon) < nearest_distance) {
          nearest = static_cast<int>(s);
          nearest_distance = std::hypot(plane, polygon);
          nearest_plane = plane;
          nearest_polygon = polygon;
          nearest_normal = normal;
        }
      }
      if (on_surface) continue;
      std::string detail = Name(leg) + " foot at " + Point(foot.position) + " is on no contact surface: ";
      if (nearest < 0) {
        detail += "there are no contact surfaces";
      } else {
        detail += "the nearest, surface " + std::to_string(nearest) + ", is " + Num(nearest_plane, 4) +
                  " m from its plane and " + Num(nearest_polygon, 4) + " m outside its polygon (tolerance " +
                  Num(tol, 4) + " m), with a normal difference of " + Num(nearest_normal, 4) + " (tolerance " +
                  Num(config_.normal_tolerance, 4) + ")";
      }
      sink_.Add(i, "surface", detail);
    }
  }

  void CheckOneLeg(int i, const WholeBodyState& state, const WholeBodyState* previous) {
    if (state.moving_leg < -1 || state.moving_leg >= kNumLegs) {
      sink_.Add(i, "one_leg", "moving_leg is " + std::to_string(state.moving_leg) + ", expected -1 or a leg index");
      return;
    }
    if (previous == nullptr) {
      if (state.moving_leg != -1) {
        sink_.Add(i, "one_leg",
                  "the first state has moving_leg " + Name(kAllLegs[static_cast<std::size_t>(state.moving_leg)]) +
                      ", expected none");
      }
      return;
    }
    std::vector<Leg> changed;
    std::string moves;
    for (Leg leg : kAllLegs) {
      const auto l = static_cast<std::size_t>(Index(leg));
      const double moved = (state.feet[l].position - previous->feet[l].position).norm();
      const double turned = (state.feet[l].normal - previous->feet[l].normal).norm();
      if (moved > config_.contact_change_tolerance || turned > config_.normal_tolerance) {
        changed.push_back(leg);
        moves += (moves.empty() ? "" : ", ") + Name(leg) + " moves " + Num(moved, 4) + " m";
      }
    }
    const std::string expected =
        state.moving_leg < 0 ? std::string("none")
                             : Name(kAllLegs[static_cast<std::size_t>(state.moving_leg)]);
    if (state.moving_leg < 0) {
      sink_.Add(i, "one_leg", "moving_leg is none, expected the leg that steps from state " + std::to_string(i - 1));
    } else if (changed.empty()) {
      sink_.Add(i, "one_leg",
                "no foot changes its contact from state " + std::to_string(i - 1) + ", expected moving_leg " +
                    expected + " to step (threshold " + Num(config_.contact_change_tolerance, 4) + " m)");
    } else if (changed.size() > 1) {
      sink_.Add(i, "one_leg",
                std::to_string(changed.size()) + " feet change their contact from state " + std::to_string(i - 1) +
                    " (" + moves + "), expected only moving_leg " + expected);
    } else if (Index(changed.front()) != state.moving_leg) {
      sink_.Add(i, "one_leg", moves + " from state " + std::to_string(i - 1) + ", but moving_leg is " + expected);
    }
  }

  void CheckJointBounds(int i, const WholeBodyState& state) {
    std::string out;
    for (Leg leg : kAllLegs) {
      const Eigen::Vector3d q = LegJoints(state.joints, leg);
      if (robot_.WithinJointBounds(leg, q)) continue;
      const Eigen::Vector3d lower = robot_.LegLowerBounds(leg), upper = robot_.LegUpperBounds(leg);
      for (int j = 0; j < kJointsPerLeg; ++j) {
        if (q[j] < lower[j] - 1e-9 || q[j] > upper[j] + 1e-9) {
          out += (out.empty() ? "" : "; ") + JointName(leg, j) + " = " + Num(q[j], 4) + " rad outside [" +
                 Num(lower[j], 4) + ", " + Num(upper[j], 4) + "]";
        }
      }
    }
    if (!out.empty()) sink_.Add(i, "joint_bounds", out);
  }

  /// One leg within the kinematic margins, or a description of how it is not.
  std::string MarginViolation(Leg leg, const Eigen::Vector3d& p_B, const Eigen::Vector3d& q_leg, double reach) const {
    const double distance = (p_B - robot_.HipPosition(leg)).norm();
    std::string out;
    if (distance > reach + 1e-9) {
      out = Name(leg) + " foot " + Num(distance, 4) + " m from its hip, at most " + Num(reach, 4) + " m";
    }
    if (std::abs(q_leg.z()) < robot_.Margins().min_knee_bend_rad - 1e-9) {
      out += (out.empty() ? "" : ", ") + JointName(leg, 2) + " bent " + Num(std::abs(q_leg.z()), 4) +
             " rad, at least " + Num(robot_.Margins().min_knee_bend_rad, 4) + " rad";
    }
    return out;
  }

  void CheckKinematicMargins(int i, const WholeBodyState& state, const std::optional<LiftOff>& lift_off) {
    const Eigen::Isometry3d T_BW = BasePose(state).inverse();
    std::string out;
    for (Leg leg : kAllLegs) {
      const Eigen::Vector3d p_B = T_BW * state.feet[static_cast<std::size_t>(Index(leg))].position;
      const std::string v = MarginViolation(leg, p_B, LegJoints(state.joints, leg), robot_.Margins().max_stance_hip_distance_m);
      if (!v.empty()) out += (out.empty() ? "" : "; ") + v;
    }
    // At lift-off the trunk is at this state's pose and the swing foot still on its old foothold
    // (out of reach there: reported by "joint_bounds").
    if (lift_off && lift_off->ik.ok()) {
      const std::string v = MarginViolation(lift_off->swing, lift_off->foot_B, lift_off->ik.q,
                                            robot_.Margins().max_lift_off_hip_distance_m);
      if (!v.empty()) out += (out.empty() ? "" : "; ") + std::string("at lift-off ") + v;
    }
    if (!out.empty()) sink_.Add(i, "kinematic_margin", out);
  }

  void CheckForwardKinematics(int i, const WholeBodyState& state) {
    const Eigen::Isometry3d base_W = BasePose(state);
    std::string out;
    for (Leg leg : kAllLegs) {
      const Eigen::Vector3d p_W = base_W * robot_.FootPosition(leg, LegJoints(state.joints, leg));
      const Eigen::Vector3d& foot = state.feet[static_cast<std::size_t>(Index(leg))].position;
      const double error = (p_W - foot).norm();
      if (!(error <= config_.fk_tolerance)) {
        out += (out.empty() ? "" : "; ") + Name(leg) + " joints put the foot at " + Point(p_W) + ", " +
               Num(error, 5) + " m from its position " + Point(foot);
      }
    }
    if (!out.empty()) sink_.Add(i, "fk", out + " (tolerance " + Num(config_.fk_tolerance, 5) + " m)");
  }

  void CheckCollision(int i, const WholeBodyState& state) {
    const std::array<bool, kNumLegs> all_feet = {true, true, true, true};
    const CollisionReport terrain = collision_->CheckRobot(BasePose(state), state.joints, all_feet);
    if (terrain.collision) {
      sink_.Add(i, "collision",
                terrain.first_shape + " hits the " + terrain.obstacle + " (penetration " + Num(terrain.penetration, 4) +
                    " m)");
    }
    const CollisionReport self = collision_->CheckSelf(state.joints);
    if (self.collision) {
      sink_.Add(i, "self_collision",
                self.first_shape + " hits " + self.obstacle + " (penetration " + Num(self.penetration, 4) + " m)");
    }
  }

  Eigen::Vector3d CenterOfMass(const Eigen::Isometry3d& base_W, const JointVector& q) const {
    return base_W * robot_.CenterOfMass(q);
  }

  void CheckStabilityAndTorques(int i, const WholeBodyState& state) {
    const Eigen::Isometry3d base_W = BasePose(state);
    const Eigen::Vector3d com_W = CenterOfMass(base_W, state.joints);
    std::vector<ContactPoint> contacts;
    for (const FootContact& foot : state.feet) contacts.push_back(ContactPoint{foot.position, foot.normal});
    equilibrium_.SetContacts(contacts);
    const EquilibriumResult result = equilibrium_.Robustness(com_W);
    report_->min_robustness_N = std::min(report_->min_robustness_N, result.robustness_N);
    if (!(result.robustness_N >= config_.robustness_threshold_N)) {
      std::string detail = "robustness " + Num(result.robustness_N, 3) + " N at the CoM " + Point(com_W) +
                           ", expected at least " + Num(config_.robustness_threshold_N, 3) + " N";
      if (result.status != EquilibriumStatus::kBalanced) {
        detail += " (" + std::string(ToString(result.status)) + (result.reason.empty() ? "" : ": " + result.reason) + ")";
      }
      sink_.Add(i, "stability", detail);
    }
    if (!result.feasible) return;  // no forces inside the cones: nothing to hold with the joints
    CheckTorques(i, "", base_W, state.joints, state.feet, -1, com_W);
  }

  /// The stance of every foot but `skip`'s holds the weight as the controller spreads it, within
  /// the torque limit.
  void CheckTorques(int i, const std::string& phase, const Eigen::Isometry3d& base_W, const JointVector& q,
                    const std::array<FootContact, kNumLegs>& feet, int skip, const Eigen::Vector3d& com_W) {
    std::vector<StanceFoot> stance = StanceFeet(feet, skip);
    for (StanceFoot& f : stance) f.normal_W.normalize();  // a plan's normals are unit within a tolerance
    ForceDistributionParams params;
    params.friction = config_.equilibrium.friction;
    params.min_normal_force_N = config_.min_normal_force_N;
    const StanceTorques t = ComputeStanceTorques(robot_, base_W, q, stance, com_W, params);
    const std::string prefix = phase.empty() ? "" : phase + " ";
    if (!t.balanced) {
      sink_.Add(i, "torque", prefix + "the contact forces cannot hold the weight at the CoM " + Point(com_W));
      return;
    }
    report_->max_torque_Nm = std::max(report_->max_torque_Nm, t.max_abs_Nm);
    int over = 0;
    for (int j = 0; j < kNumJoints; ++j) over += std::abs(t.tau[j]) > config_.torque_limit_Nm ? 1 : 0;
    if (over > 0) {
      sink_.Add(i, "torque",
                prefix + JointName(t.worst_joint) + " needs " + Num(t.max_abs_Nm, 2) + " N m, limit " +
                    Num(config_.torque_limit_Nm, 2) + " N m (" + std::to_string(over) +
                    (over == 1 ? " joint" : " joints") + " over the limit)");
    }
  }

  void CheckSupportMargin(int i, const WholeBodyState& previous, const WholeBodyState& state, const LiftOff& lift_off) {
    const Leg swing = lift_off.swing;
    std::vector<Eigen::Vector3d> stance;
    std::string stance_names;
    for (Leg leg : kAllLegs) {
      if (leg == swing) continue;
      stance.push_back(state.feet[static_cast<std::size_t>(Index(leg))].position);
      stance_names += (stance_names.empty() ? "" : ", ") + Name(leg);
    }
    const Eigen::Isometry3d base_W = BasePose(state);

    // Lift-off: the trunk has moved to this state's pose, the swing foot is still on its old
    // foothold, the stance legs are already in this state's configuration.
    const IkResult& ik = lift_off.ik;
    if (ik.ok()) {
      JointVector q_lift = state.joints;
      SetLegJoints(q_lift, swing, ik.q);
      const Eigen::Vector3d com_lift = CenterOfMass(base_W, q_lift);
      CheckCoMInStance(i, "at lift-off", com_lift, stance, stance_names);
      if (SupportPolygonMargin(stance, com_lift) >= 0.0) {
        CheckTorques(i, "at lift-off", base_W, q_lift, previous.feet, Index(swing), com_lift);
      }
    } else {
      sink_.Add(i, "joint_bounds",
                "at lift-off (trunk at this state's pose) " + Name(swing) + " cannot keep its foothold of state " +
                    std::to_string(i - 1) + ": " + ik.reason);
    }
    CheckCoMInStance(i, "at touchdown", CenterOfMass(base_W, state.joints), stance, stance_names);
  }

  void CheckCoMInStance(int i, const char* phase, const Eigen::Vector3d& com_W,
                        const std::vector<Eigen::Vector3d>& stance, const std::string& stance_names) {
    const double margin = SupportPolygonMargin(stance, com_W);
    report_->min_support_margin_m = std::min(report_->min_support_margin_m, margin);
    if (!(margin >= config_.support_margin_m)) {
      sink_.Add(i, "support_margin",
                std::string(phase) + " the CoM projection is " + Num(std::abs(margin), 4) + " m " +
                    (margin >= 0.0 ? "inside" : "outside") + " the support triangle of " + stance_names +
                    ", expected at least " + Num(config_.support_margin_m, 4) + " m inside");
    }
  }

  /// The trunk's straight move from `previous`'s pose to `state`'s on previous's four feet.
  void CheckShift(int i, const WholeBodyState& previous, const WholeBodyState& state) {
    const int n = config_.shift_checks;
    const std::array<bool, kNumLegs> all_feet = {true, true, true, true};
    for (int k = 1; k <= n; ++k) {
      const double w = static_cast<double>(k) / static_cast<double>(n + 1);
      Eigen::Vector3d rpy = previous.base_rpy + w * (state.base_rpy - previous.base_rpy);
      rpy.z() = WrapAngle(previous.base_rpy.z() + w * WrapAngle(state.base_rpy.z() - previous.base_rpy.z()));
      const Eigen::Isometry3d base_W =
          PoseFromRpy(previous.base_position + w * (state.base_position - previous.base_position), rpy);
      const std::string phase = "at " + Num(w, 2) + " of the shift from state " + std::to_string(i - 1);
      const std::string at = phase + ": ";
      JointVector q = JointVector::Zero();
      for (Leg leg : kAllLegs) {
        const IkResult ik = robot_.SolveLegIk(leg, base_W.inverse() * previous.feet[static_cast<std::size_t>(Index(leg))].position);
        if (!ik.ok()) {
          sink_.Add(i, "shift", at + Name(leg) + " cannot keep its foothold: " + ik.reason);
          return;
        }
        SetLegJoints(q, leg, ik.q);
      }
      const Eigen::Vector3d com_W = CenterOfMass(base_W, q);
      std::vector<Eigen::Vector3d> feet;
      for (const FootContact& f : previous.feet) feet.push_back(f.position);
      const double margin = SupportPolygonMargin(feet, com_W);
      report_->min_support_margin_m = std::min(report_->min_support_margin_m, margin);
      if (!(margin >= config_.support_margin_m)) {
        sink_.Add(i, "shift", at + "the CoM projection is " + Num(margin, 4) + " m inside the four feet's polygon, expected at least " +
                                  Num(config_.support_margin_m, 4) + " m");
        return;
      }
      if (collision_) {
        const CollisionReport hit = collision_->CheckRobot(base_W, q, all_feet);
        if (hit.collision) {
          sink_.Add(i, "shift", at + hit.first_shape + " hits the " + hit.obstacle);
          return;
        }
      }
      const int before = report_->violation_count;
      CheckTorques(i, phase, base_W, q, previous.feet, -1, com_W);
      if (report_->violation_count > before) return;
    }
  }

  /// The moving leg along the swing path the controller walks.
  void CheckSwing(int i, const WholeBodyState& previous, const WholeBodyState& state, const LiftOff& lift_off) {
    const Leg leg = lift_off.swing;
    const std::size_t l = static_cast<std::size_t>(Index(leg));
    const Eigen::Isometry3d base_W = BasePose(state);
    const Eigen::Vector3d& from = previous.feet[l].position;
    const Eigen::Vector3d& to = state.feet[l].position;
    const SwingTrajectory path =
        state.HasSwing() ? SwingTrajectory::Given(from, to, state.swing_apex_z, state.swing_bow, config_.stance.config.swing)
                         : stance_.PlanSwing(leg, from, to, base_W, state.joints);
    for (const Eigen::Vector3d& foot_W : path.LegCheckPoints()) {
      const std::string at = Name(leg) + "'s swing, foot at " + Point(foot_W) + ": ";
      const IkResult ik = robot_.SolveLegIk(leg, base_W.inverse() * foot_W);
      if (!ik.ok()) {
        sink_.Add(i, "swing", at + "out of reach: " + ik.reason);
        return;
      }
      // The foot itself as a stance foot's: its clearance is the path's (apex over the terrain).
      const CollisionReport hit = collision_->CheckLeg(leg, base_W, ik.q, true);
      if (hit.collision) {
        sink_.Add(i, "swing", at + hit.first_shape + " hits the " + hit.obstacle);
        return;
      }
      JointVector q = state.joints;
      SetLegJoints(q, leg, ik.q);
      const CollisionReport self = collision_->CheckSelf(q);
      if (self.collision) {
        sink_.Add(i, "swing", at + self.first_shape + " hits " + self.obstacle);
        return;
      }
    }
  }

  const RobotModel& robot_;
  const PlanCheckConfig& config_;
  PlanCheckReport* report_;
  ViolationSink sink_;
  StaticEquilibrium equilibrium_;
  StanceChecker stance_;
  std::vector<SurfaceGeometry> surfaces_;
  std::unique_ptr<RobotTerrainCollision> collision_;
};

nlohmann::json FiniteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

PlanCheckConfig PlanCheckConfig::FromConfigs(const RobotModel& robot, const EquilibriumConfig& equilibrium,
                                             const StanceRules& stance) {
  PlanCheckConfig config;
  config.robustness_threshold_N = equilibrium.robustness_threshold_N;
  config.support_margin_m = stance.config.support_margin_m;
  config.min_normal_force_N = stance.config.min_normal_force_N;
  config.shift_checks = stance.config.transit_checks;
  config.stance = stance;
  config.torque_limit_Nm = robot.ContinuousTorqueLimit();
  config.equilibrium = equilibrium;
  return config;
}

void PlanCheckConfig::Validate() const {
  const auto fail = [](const char* key, const char* expected, double got) {
    throw InputError(std::string("PlanCheckConfig: '") + key + "': expected " + expected + ", got " +
                     Num(got, 6));
  };
  const auto non_negative = [&](const char* key, double value) {
    if (!(std::isfinite(value) && value >= 0.0)) fail(key, "a finite value >= 0", value);
  };
  non_negative("surface_tolerance", surface_tolerance);
  non_negative("normal_tolerance", normal_tolerance);
  non_negative("fk_tolerance", fk_tolerance);
  non_negative("contact_change_tolerance", contact_change_tolerance);
  if (!std::isfinite(robustness_threshold_N)) {
    fail("robustness_threshold_N", "a finite value (see PlanCheckConfig::FromConfigs)", robustness_threshold_N);
  }
  if (!std::isfinite(support_margin_m)) {
    fail("support_margin_m", "a finite value (see PlanCheckConfig::FromConfigs)", support_margin_m);
  }
  if (!(std::isfinite(torque_limit_Nm) && torque_limit_Nm > 0.0)) {
    fail("torque_limit_Nm", "a finite value > 0 (see PlanCheckConfig::FromConfigs)", torque_limit_Nm);
  }
  if (!(std::isfinite(min_normal_force_N) && min_normal_force_N >= 0.0)) {
    fail("min_normal_force_N", "a finite value >= 0", min_normal_force_N);
  }
  if (max_violations < 0) fail("max_violations", "a count >= 0", max_violations);
  if (shift_checks < 1) fail("shift_checks", "a count >= 1", shift_checks);
  stance.config.Validate("PlanCheckConfig: stance");
  equilibrium.Validate("PlanCheckConfig: equilibrium");
}

std::string PlanCheckReport::Summary() const {
  std::string metrics = "min robustness " + Num(min_robustness_N, 2) + " N, max torque " + Num(max_torque_Nm, 2) +
                        " N m, min support margin " + Num(min_support_margin_m, 4) + " m";
  if (timed) {
    metrics += "; its dynamic walk: " + std::to_string(walk_violations.size()) + " of " + std::to_string(states - 1) +
               " steps fail a check, min ZMP margin " + Num(min_zmp_margin_m, 4) + " m, max torque " +
               Num(max_walk_torque_Nm, 2) + " N m";
  }
  if (ok) return "plan passes: " + std::to_string(states) + " states, " + metrics;
  std::vector<std::string> checks;
  for (const auto& v : violations) {
    if (std::find(checks.begin(), checks.end(), v.check) == checks.end()) checks.push_back(v.check);
  }
  std::string names;
  for (const auto& c : checks) names += (names.empty() ? "" : ", ") + c;
  return "plan fails: " + std::to_string(violation_count) + (violation_count == 1 ? " violation" : " violations") +
         " in " + std::to_string(states) + " states (" + names + "); " + metrics;
}

PlanCheckReport CheckPlan(const RobotModel& robot, const TriangleMesh& terrain,
                          const std::vector<AffordanceSurface>& surfaces, const ContactPlan& plan,
                          const PlanCheckConfig& config) {
  config.Validate();
  if (plan.states.empty()) throw InputError("contact plan: expected at least one state, got none");
  RequireFinite(plan);
  PlanCheckReport report;
  report.states = static_cast<int>(plan.states.size());
  PlanChecker checker(robot, terrain, surfaces, config, &report);
  checker.Check(plan);
  report.ok = report.violation_count == 0;
  return report;
}

PlanCheckReport CheckPlanForScenario(const std::string& config_dir, const Scenario& scenario,
                                     const ContactPlan& plan) {
  const RobotModel robot = RobotModel::LoadDefault(config_dir);
  const EquilibriumConfig equilibrium = EquilibriumConfig::LoadFile(config_dir + "/equilibrium.yaml");
  AffordanceExtractor extractor(AffordanceConfig::LoadFile(config_dir + "/affordance.yaml"));
  const std::vector<AffordanceSurface> surfaces = extractor.Extract(scenario.terrain_mesh);
  return CheckPlan(robot, scenario.terrain_mesh, surfaces, plan,
                   PlanCheckConfig::FromConfigs(robot, equilibrium, StanceRules::LoadFromDir(config_dir)));
}

namespace {

nlohmann::json ViolationsJson(const std::vector<PlanViolation>& violations) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& v : violations) out.push_back({{"state", v.state}, {"check", v.check}, {"detail", v.detail}});
  return out;
}

}  // namespace

nlohmann::json PlanCheckReportToJson(const PlanCheckReport& report) {
  nlohmann::json j = {{"ok", report.ok},
      {"states", report.states},  // the count (kept for compatibility), as state_count
      {"state_count", report.states},
      {"violation_count", report.violation_count},
      {"violations", ViolationsJson(report.violations)},
      {"min_robustness_N", FiniteOrNull(report.min_robustness_N)},
      {"max_torque_Nm", FiniteOrNull(report.max_torque_Nm)},
      {"min_support_margin_m", FiniteOrNull(report.min_support_margin_m)},
      {"walk", nullptr}};
  if (report.timed) {
    j["walk"] = {{"ok", report.walk_violations.empty()},
                 {"violations", ViolationsJson(report.walk_violations)},
                 {"min_zmp_margin_m", FiniteOrNull(report.min_zmp_margin_m)},
                 {"max_torque_Nm", FiniteOrNull(report.max_walk_torque_Nm)}};
  }
  AddSchemaKeys(j);
  return j;
}

}  // namespace rbcp
