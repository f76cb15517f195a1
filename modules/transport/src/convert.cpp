#include "rbcp/transport/convert.h"

#include <cmath>

#include "rbcp/core/error.h"

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

}  // namespace

rbcp_msgs::terrain_mesh_t ToTerrainMsg(const TriangleMesh& mesh, int64_t utime, const std::string& scenario_name) {
  rbcp_msgs::terrain_mesh_t msg;
  msg.utime = utime;
  msg.scenario_name = scenario_name;
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
  return mesh;
}

rbcp_msgs::affordance_set_t ToAffordanceMsg(const std::vector<AffordanceSurface>& surfaces, int64_t utime) {
  rbcp_msgs::affordance_set_t msg;
  msg.utime = utime;
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
    out.push_back(std::move(surface));
  }
  return out;
}

rbcp_msgs::contact_plan_t ToContactPlanMsg(const ContactPlan& plan, int64_t utime, int64_t request_id,
                                           int64_t plan_seq, int64_t start_utime) {
  rbcp_msgs::contact_plan_t msg;
  msg.utime = utime;
  msg.request_id = request_id;
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
    if (in.moving_leg < -1 || in.moving_leg >= kNumLegs) {
      throw InputError(what + ": moving_leg expected -1..3, got " + std::to_string(in.moving_leg));
    }
    s.moving_leg = in.moving_leg;
    plan.states.push_back(s);
  }
  return plan;
}

rbcp_msgs::robot_state_t ToRobotStateMsg(const RobotState& state, const ControllerProgress& progress) {
  rbcp_msgs::robot_state_t msg{};
  msg.plan_seq = progress.plan_seq;
  msg.steps_done = progress.steps_done;
  msg.awaiting_plan = progress.awaiting_since.has_value();
  msg.awaiting_since = progress.awaiting_since.value_or(0);
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
  const Eigen::Quaterniond q(msg.base_orientation[0], msg.base_orientation[1], msg.base_orientation[2],
                             msg.base_orientation[3]);
  if (std::abs(q.norm() - 1.0) > 1e-3) {
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

ControllerProgress ProgressFromRobotStateMsg(const rbcp_msgs::robot_state_t& msg) {
  if (msg.steps_done < 0) {
    throw InputError("robot state: steps_done expected >= 0, got " + std::to_string(msg.steps_done));
  }
  if (msg.awaiting_plan && msg.awaiting_since > msg.utime) {
    throw InputError("robot state: awaiting_since " + std::to_string(msg.awaiting_since) +
                     " us expected at or before the message's utime " + std::to_string(msg.utime) + " us");
  }
  ControllerProgress progress;
  progress.plan_seq = msg.plan_seq;
  progress.steps_done = msg.steps_done;
  if (msg.awaiting_plan) progress.awaiting_since = msg.awaiting_since;
  return progress;
}

}  // namespace rbcp::transport
