#include "rbcp/transport/convert.h"

#include <cmath>
#include <cstring>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"

namespace rbcp::transport {
namespace {

template <typename Rows>
void CheckRows(const Rows& rows, int32_t count, std::size_t width, const std::string& what) {
  if (count < 0 || rows.size() != static_cast<std::size_t>(count)) {
    throw InputError(what + ": count " + std::to_string(count) + " disagrees with " + std::to_string(rows.size()) +
                     " entries");
  }
  for (const auto& row : rows) {
    if (row.size() != width) throw InputError(what + ": expected rows of " + std::to_string(width) + " values");
  }
}

Eigen::Vector3d Vec3(const double* v) { return {v[0], v[1], v[2]}; }

/// A plan state's swing: its apex within this of the base height, its bow at most this long [m].
constexpr double kMaxSwingApexOffsetM = 2.0;
constexpr double kMaxSwingBowM = 0.5;

/// Finite and within kMaxCoordinate_m of the origin along every axis.
bool Sane(const Eigen::Vector3d& p) { return p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxCoordinate_m; }

std::string Point(const Eigen::Vector3d& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

/// "" when p is finite and within kMaxCoordinate_m; otherwise the reason, naming `what`.
/// What is wrong with a position in a message, e.g. "is not finite", or nullopt.
std::optional<std::string> PositionProblem(const Eigen::Vector3d& p) {
  if (!p.allFinite()) return std::string("is not finite");
  if (!Sane(p)) return Point(p) + " is beyond " + FixedNumber(kMaxCoordinate_m, 0) + " m of the origin";
  return std::nullopt;
}

double Norm4(const double q[4]) { return std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]); }

double YawOf(const double q[4]) {  // (w, x, y, z), base to world
  return std::atan2(2.0 * (q[0] * q[3] + q[1] * q[2]), 1.0 - 2.0 * (q[2] * q[2] + q[3] * q[3]));
}

}  // namespace

int64_t TerrainId(const TriangleMesh& mesh) {
  // FNV-1a over 64-bit words (each coordinate's bits, each triangle's indices), then a final mix
  // so that every bit of the id depends on every word.
  uint64_t h = 0xcbf29ce484222325ULL;
  const auto add = [&h](uint64_t word) {
    h ^= word;
    h *= 0x100000001b3ULL;
  };
  add(mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) {
      uint64_t bits = 0;
      std::memcpy(&bits, &v[k], sizeof bits);
      add(bits);
    }
  }
  add(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    add((static_cast<uint64_t>(static_cast<uint32_t>(t[0])) << 32) | static_cast<uint32_t>(t[1]));
    add(static_cast<uint32_t>(t[2]));
  }
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  return h == 0 ? 1 : static_cast<int64_t>(h);
}

rbcp_msgs::terrain_mesh_t ToTerrainMsg(const TriangleMesh& mesh, int64_t utime, const std::string& scenario_name) {
  rbcp_msgs::terrain_mesh_t msg;
  msg.utime = utime;
  msg.scenario_name = scenario_name;
  msg.terrain_id = TerrainId(mesh);
  msg.num_vertices = static_cast<int32_t>(mesh.vertices.size());
  msg.vertices.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) msg.vertices.push_back({v.x(), v.y(), v.z()});
  msg.num_triangles = static_cast<int32_t>(mesh.triangles.size());
  msg.triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) msg.triangles.push_back({t[0], t[1], t[2]});
  return msg;
}

TriangleMesh FromTerrainMsg(const rbcp_msgs::terrain_mesh_t& msg) {
  CheckRows(msg.vertices, msg.num_vertices, 3, "terrain vertices");
  CheckRows(msg.triangles, msg.num_triangles, 3, "terrain triangles");
  TriangleMesh mesh;
  mesh.vertices.reserve(msg.vertices.size());
  for (const auto& v : msg.vertices) mesh.vertices.emplace_back(v[0], v[1], v[2]);
  mesh.triangles.reserve(msg.triangles.size());
  for (const auto& t : msg.triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
  const std::string problem = ValidateMesh(mesh);
  if (!problem.empty()) throw InputError("terrain mesh: " + problem);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (auto bad = PositionProblem(mesh.vertices[i])) {
      throw InputError("terrain mesh: vertex " + std::to_string(i) + " " + *bad);
    }
  }
  if (const int64_t id = TerrainId(mesh); id != msg.terrain_id) {
    throw InputError("terrain mesh: terrain_id " + std::to_string(msg.terrain_id) + " is not its content's (" +
                     std::to_string(id) + ")");
  }
  return mesh;
}

rbcp_msgs::affordance_set_t ToAffordanceMsg(const std::vector<AffordanceSurface>& surfaces, int64_t utime,
                                            int64_t terrain_id) {
  rbcp_msgs::affordance_set_t msg;
  msg.utime = utime;
  msg.terrain_id = terrain_id;
  msg.num_surfaces = static_cast<int32_t>(surfaces.size());
  msg.surfaces.reserve(surfaces.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const AffordanceSurface& s = surfaces[i];
    rbcp_msgs::affordance_surface_t out;
    out.id = static_cast<int32_t>(i);
    out.num_vertices = static_cast<int32_t>(s.vertices.size());
    for (const auto& v : s.vertices) out.vertices.push_back({v.x(), v.y(), v.z()});
    for (int k = 0; k < 3; ++k) out.normal[k] = s.normal[k];
    out.area = s.area;
    msg.surfaces.push_back(std::move(out));
  }
  return msg;
}

std::vector<AffordanceSurface> FromAffordanceMsg(const rbcp_msgs::affordance_set_t& msg) {
  if (msg.num_surfaces < 0 || msg.surfaces.size() != static_cast<std::size_t>(msg.num_surfaces)) {
    throw InputError("affordance set: count " + std::to_string(msg.num_surfaces) + " disagrees with " +
                     std::to_string(msg.surfaces.size()) + " surfaces");
  }
  std::vector<AffordanceSurface> out;
  out.reserve(msg.surfaces.size());
  for (const auto& s : msg.surfaces) {
    const std::string what = "affordance surface " + std::to_string(s.id);
    CheckRows(s.vertices, s.num_vertices, 3, what);
    if (s.num_vertices < 3) throw InputError(what + ": expected at least 3 vertices, got " + std::to_string(s.num_vertices));
    AffordanceSurface surface;
    for (const auto& v : s.vertices) surface.vertices.emplace_back(v[0], v[1], v[2]);
    surface.normal = Vec3(s.normal);
    surface.area = s.area;
    bool finite = surface.normal.allFinite() && std::isfinite(surface.area);
    for (const auto& v : surface.vertices) finite = finite && v.allFinite();
    if (!finite) throw InputError(what + ": expected finite values");
    for (std::size_t k = 0; k < surface.vertices.size(); ++k) {
      if (auto bad = PositionProblem(surface.vertices[k])) {
        throw InputError(what + ": vertex " + std::to_string(k) + " " + *bad);
      }
    }
    if (std::abs(surface.normal.norm() - 1.0) > kUnitTolerance) {
      throw InputError(what + ": expected a unit normal, got " + Point(surface.normal) + " of norm " +
                       std::to_string(surface.normal.norm()));
    }
    if (surface.area < 0.0) throw InputError(what + ": expected an area >= 0, got " + std::to_string(surface.area));
    surface.normal.normalize();  // exactly unit for the planners, once within the tolerance
    out.push_back(std::move(surface));
  }
  return out;
}

rbcp_msgs::contact_plan_t ToContactPlanMsg(const ContactPlan& plan, int64_t utime, int64_t request_id,
                                           int64_t terrain_id, int64_t plan_seq, int64_t start_utime) {
  rbcp_msgs::contact_plan_t msg;
  msg.utime = utime;
  msg.request_id = request_id;
  msg.terrain_id = terrain_id;
  msg.plan_seq = plan_seq;
  msg.start_utime = start_utime;
  msg.reaches_goal = plan.reaches_goal;
  msg.num_states = static_cast<int32_t>(plan.states.size());
  msg.states.reserve(plan.states.size());
  for (const WholeBodyState& s : plan.states) {
    rbcp_msgs::whole_body_state_t out{};
    for (int k = 0; k < 3; ++k) {
      out.base_position[k] = s.base_position[k];
      out.base_rpy[k] = s.base_rpy[k];
    }
    for (int j = 0; j < 12; ++j) out.joint_position[j] = s.joints[j];
    for (int leg = 0; leg < kNumLegs; ++leg) {
      for (int k = 0; k < 3; ++k) {
        out.foot_position[leg][k] = s.feet[static_cast<std::size_t>(leg)].position[k];
        out.foot_normal[leg][k] = s.feet[static_cast<std::size_t>(leg)].normal[k];
      }
    }
    out.moving_leg = static_cast<int8_t>(s.moving_leg);
    out.swing_apex_z = s.swing_apex_z;
    out.swing_bow[0] = s.swing_bow.x();
    out.swing_bow[1] = s.swing_bow.y();
    out.lift_off_s = s.lift_off_s;
    out.touch_down_s = s.touch_down_s;
    msg.states.push_back(out);
  }
  return msg;
}

ContactPlan FromContactPlanMsg(const rbcp_msgs::contact_plan_t& msg) {
  if (msg.num_states < 0 || msg.states.size() != static_cast<std::size_t>(msg.num_states)) {
    throw InputError("contact plan: count " + std::to_string(msg.num_states) + " disagrees with " +
                     std::to_string(msg.states.size()) + " states");
  }
  ContactPlan plan;
  plan.reaches_goal = msg.reaches_goal;
  plan.states.reserve(msg.states.size());
  for (std::size_t i = 0; i < msg.states.size(); ++i) {
    const auto& in = msg.states[i];
    const std::string what = "contact plan state " + std::to_string(i);
    WholeBodyState s;
    s.base_position = Vec3(in.base_position);
    s.base_rpy = Vec3(in.base_rpy);
    for (int j = 0; j < 12; ++j) s.joints[j] = in.joint_position[j];
    bool finite = s.base_position.allFinite() && s.base_rpy.allFinite() && s.joints.allFinite();
    for (int leg = 0; leg < kNumLegs; ++leg) {
      auto& foot = s.feet[static_cast<std::size_t>(leg)];
      foot.position = Vec3(in.foot_position[leg]);
      foot.normal = Vec3(in.foot_normal[leg]);
      finite = finite && foot.position.allFinite() && foot.normal.allFinite();
    }
    if (!finite) throw InputError(what + ": expected finite values");
    if (auto bad = PositionProblem(s.base_position)) throw InputError(what + ": base position " + *bad);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      if (auto bad = PositionProblem(s.feet[static_cast<std::size_t>(leg)].position)) {
        throw InputError(what + ": foot " + std::to_string(leg) + " " + *bad);
      }
    }
    if (in.moving_leg < -1 || in.moving_leg >= kNumLegs) {
      throw InputError(what + ": moving_leg expected -1..3, got " + std::to_string(in.moving_leg));
    }
    s.moving_leg = in.moving_leg;
    // A swing is given (a finite apex within reach of the footholds, a small bow) or not at all.
    if (std::isfinite(in.swing_apex_z)) {
      const Eigen::Vector2d bow(in.swing_bow[0], in.swing_bow[1]);
      if (in.moving_leg < 0 || !bow.allFinite() || bow.norm() > kMaxSwingBowM ||
          std::abs(in.swing_apex_z - s.base_position.z()) > kMaxSwingApexOffsetM) {
        throw InputError(what + ": expected a swing apex within " + FixedNumber(kMaxSwingApexOffsetM, 1) +
                         " m of the base height and a bow up to " + FixedNumber(kMaxSwingBowM, 1) + " m, got apex " +
                         FixedNumber(in.swing_apex_z, 3) + " m and bow " + FixedNumber(bow.norm(), 3) + " m");
      }
      s.swing_apex_z = in.swing_apex_z;
      s.swing_bow = bow;
    }
    s.lift_off_s = in.lift_off_s;
    s.touch_down_s = in.touch_down_s;
    plan.states.push_back(s);
  }
  if (auto bad = TimingProblem(plan)) throw InputError("contact plan: timing: " + *bad);
  return plan;
}

rbcp_msgs::robot_state_t ToRobotStateMsg(const RobotState& state) {
  rbcp_msgs::robot_state_t msg{};
  msg.utime = static_cast<int64_t>(std::llround(state.t * 1e6));
  for (int k = 0; k < 3; ++k) {
    msg.base_position[k] = state.base_position_W[k];
    msg.base_linear_velocity[k] = state.base_linear_velocity_W[k];
    msg.base_angular_velocity[k] = state.base_angular_velocity_B[k];
  }
  msg.base_orientation[0] = state.base_orientation_W.w();
  msg.base_orientation[1] = state.base_orientation_W.x();
  msg.base_orientation[2] = state.base_orientation_W.y();
  msg.base_orientation[3] = state.base_orientation_W.z();
  for (int j = 0; j < kNumJoints; ++j) {
    msg.joint_position[j] = state.q[j];
    msg.joint_velocity[j] = state.qd[j];
    msg.joint_torque[j] = state.tau[j];
  }
  for (int i = 0; i < kNumLegs; ++i) {
    msg.foot_contact[i] = state.foot_contact[static_cast<std::size_t>(i)];
    for (int k = 0; k < 3; ++k) msg.foot_force[i][k] = state.foot_force_W[static_cast<std::size_t>(i)][k];
  }
  return msg;
}

RobotState FromRobotStateMsg(const rbcp_msgs::robot_state_t& msg) {
  const bool finite = AllFinite(msg.base_position, 3) && AllFinite(msg.base_orientation, 4) &&
                      AllFinite(msg.base_linear_velocity, 3) && AllFinite(msg.base_angular_velocity, 3) &&
                      AllFinite(msg.joint_position, kNumJoints) && AllFinite(msg.joint_velocity, kNumJoints) &&
                      AllFinite(msg.joint_torque, kNumJoints) && AllFinite(&msg.foot_force[0][0], 3 * kNumLegs);
  if (!finite) throw InputError("robot state: expected finite values");
  if (auto bad = PositionProblem(Vec3(msg.base_position))) throw InputError("robot state: base position " + *bad);
  const Eigen::Quaterniond q(msg.base_orientation[0], msg.base_orientation[1], msg.base_orientation[2],
                             msg.base_orientation[3]);
  if (std::abs(q.norm() - 1.0) > kUnitTolerance) {
    throw InputError("robot state: expected a unit base orientation quaternion, got norm " + std::to_string(q.norm()));
  }
  RobotState state;
  state.t = static_cast<double>(msg.utime) * 1e-6;
  state.base_position_W = Vec3(msg.base_position);
  state.base_orientation_W = q.normalized();
  state.base_linear_velocity_W = Vec3(msg.base_linear_velocity);
  state.base_angular_velocity_B = Vec3(msg.base_angular_velocity);
  for (int j = 0; j < kNumJoints; ++j) {
    state.q[j] = msg.joint_position[j];
    state.qd[j] = msg.joint_velocity[j];
    state.tau[j] = msg.joint_torque[j];
  }
  for (int i = 0; i < kNumLegs; ++i) {
    state.foot_contact[static_cast<std::size_t>(i)] = msg.foot_contact[i];
    state.foot_force_W[static_cast<std::size_t>(i)] = Vec3(msg.foot_force[i]);
  }
  return state;
}

rbcp_msgs::controller_status_t ToControllerStatusMsg(int64_t utime, const ControllerProgress& progress) {
  rbcp_msgs::controller_status_t msg{};
  msg.utime = utime;
  msg.plan_seq = progress.plan_seq;
  msg.steps_done = progress.steps_done;
  msg.awaiting_plan = progress.awaiting_since.has_value();
  msg.awaiting_since = progress.awaiting_since.value_or(0);
  msg.phase = progress.phase;
  msg.step = progress.step;
  msg.swing_leg = static_cast<int8_t>(progress.swing_leg);
  msg.base_error = progress.base_error_m;
  msg.step_max_base_error = progress.step_max_base_error_m;
  msg.support_margin = progress.support_margin_m;
  msg.steps_committed = progress.steps_committed;
  msg.lag_s = progress.lag_s;
  return msg;
}

ControllerProgress FromControllerStatusMsg(const rbcp_msgs::controller_status_t& msg) {
  const std::string what = "controller status: ";
  if (msg.steps_done < 0) throw InputError(what + "steps_done expected >= 0, got " + std::to_string(msg.steps_done));
  if (msg.step < 0) throw InputError(what + "step expected >= 0, got " + std::to_string(msg.step));
  if (msg.awaiting_plan && msg.awaiting_since > msg.utime) {
    throw InputError(what + "awaiting_since " + std::to_string(msg.awaiting_since) +
                     " us expected at or before the message's utime " + std::to_string(msg.utime) + " us");
  }
  if (msg.swing_leg < -1 || msg.swing_leg >= kNumLegs) {
    throw InputError(what + "swing_leg expected -1..3, got " + std::to_string(msg.swing_leg));
  }
  if (!std::isfinite(msg.base_error) || !std::isfinite(msg.step_max_base_error) || !std::isfinite(msg.support_margin)) {
    throw InputError(what + "expected finite base errors and support margin");
  }
  if (msg.steps_committed < 0) {
    throw InputError(what + "steps_committed expected >= 0, got " + std::to_string(msg.steps_committed));
  }
  if (!(msg.lag_s >= 0.0) || !std::isfinite(msg.lag_s)) throw InputError(what + "lag_s expected finite and >= 0");
  if (msg.phase.size() > 32) throw InputError(what + "phase expected a short name, got " + std::to_string(msg.phase.size()) + " bytes");
  ControllerProgress progress;
  progress.plan_seq = msg.plan_seq;
  progress.steps_done = msg.steps_done;
  if (msg.awaiting_plan) progress.awaiting_since = msg.awaiting_since;
  progress.phase = msg.phase;
  progress.step = msg.step;
  progress.swing_leg = msg.swing_leg;
  progress.base_error_m = msg.base_error;
  progress.step_max_base_error_m = msg.step_max_base_error;
  progress.support_margin_m = msg.support_margin;
  progress.steps_committed = msg.steps_committed;
  progress.lag_s = msg.lag_s;
  return progress;
}

std::vector<RootPathSample> FromRootPathMsg(const rbcp_msgs::root_path_t& msg, double max_duration_s) {
  if (msg.num_points < 0 || msg.points.size() != static_cast<std::size_t>(msg.num_points)) {
    throw InputError("root path: count " + std::to_string(msg.num_points) + " disagrees with " +
                     std::to_string(msg.points.size()) + " points");
  }
  if (msg.points.empty()) throw InputError("root path: no point");
  std::vector<RootPathSample> samples;
  samples.reserve(msg.points.size());
  for (std::size_t i = 0; i < msg.points.size(); ++i) {
    const auto& in = msg.points[i];
    const std::string what = "root path: point " + std::to_string(i);
    if (!std::isfinite(in.t) || !AllFinite(in.position, 3) || !AllFinite(in.velocity, 3) ||
        !AllFinite(in.orientation, 4)) {
      throw InputError(what + " is not finite");
    }
    if (auto bad = PositionProblem(Vec3(in.position))) throw InputError(what + ": position " + *bad);
    if (std::abs(Norm4(in.orientation) - 1.0) > kUnitTolerance) {
      throw InputError(what + ": orientation is not a unit quaternion");
    }
    if (i > 0 && !(in.t > msg.points[i - 1].t)) {
      throw InputError(what + ": times must increase, got t = " + std::to_string(in.t) + " s after " +
                       std::to_string(msg.points[i - 1].t) + " s");
    }
    RootPathSample s;
    s.t = in.t;
    s.p = Vec3(in.position);
    s.v = Vec3(in.velocity);
    s.yaw = YawOf(in.orientation);
    s.rest_yaw = s.yaw;
    samples.push_back(s);
  }
  const double duration = samples.back().t - samples.front().t;
  if (!(duration <= max_duration_s)) {
    throw InputError("root path: lasts " + std::to_string(duration) + " s, more than the limit of " +
                     FixedNumber(max_duration_s, 0) + " s");
  }
  return samples;
}

std::string PlanRequestProblem::Describe() const {
  std::string field;
  switch (kind) {
    case Kind::kGoal: field = "goal"; break;
    case Kind::kGoalYaw: field = "goal yaw"; break;
    case Kind::kStart: field = "start"; break;
    case Kind::kStartYaw: field = "start yaw"; break;
    case Kind::kTimeBudget: field = "time_budget"; break;
  }
  return "plan request: " + field + " " + detail;
}

std::optional<PlanRequestProblem> CheckPlanRequest(const rbcp_msgs::plan_request_t& msg, double max_time_budget_s) {
  using Kind = PlanRequestProblem::Kind;
  if (auto bad = PositionProblem(Vec3(msg.goal_position))) return PlanRequestProblem{Kind::kGoal, *bad};
  if (!std::isfinite(msg.goal_yaw)) return PlanRequestProblem{Kind::kGoalYaw, "is not finite"};
  if (msg.use_start) {
    if (auto bad = PositionProblem(Vec3(msg.start_position))) return PlanRequestProblem{Kind::kStart, *bad};
    if (!std::isfinite(msg.start_yaw)) return PlanRequestProblem{Kind::kStartYaw, "is not finite"};
  }
  if (!std::isfinite(msg.time_budget)) return PlanRequestProblem{Kind::kTimeBudget, "is not finite"};
  if (msg.time_budget > max_time_budget_s) {
    return PlanRequestProblem{Kind::kTimeBudget, std::to_string(msg.time_budget) + " s exceeds the limit of " +
                                                     FixedNumber(max_time_budget_s, 0) + " s"};
  }
  return std::nullopt;
}

}  // namespace rbcp::transport
