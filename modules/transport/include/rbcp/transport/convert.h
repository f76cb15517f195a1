#pragma once
/// Conversions between LCM messages and the libraries' Eigen types. Messages coming in are
/// untrusted: conversions from a message validate it and throw rbcp::InputError with the reason.

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/robot/robot_state.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::transport {

/// True when the n values of a message array are all finite.
inline bool AllFinite(const double* v, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

rbcp_msgs::terrain_mesh_t ToTerrainMsg(const TriangleMesh& mesh, int64_t utime, const std::string& scenario_name);

/// Throws InputError if the counts disagree with the arrays, a vertex is not finite, an index is
/// out of range or a triangle is degenerate.
TriangleMesh FromTerrainMsg(const rbcp_msgs::terrain_mesh_t& msg);

rbcp_msgs::affordance_set_t ToAffordanceMsg(const std::vector<AffordanceSurface>& surfaces, int64_t utime);

/// Throws InputError if counts disagree, a value is not finite or a polygon has < 3 vertices.
std::vector<AffordanceSurface> FromAffordanceMsg(const rbcp_msgs::affordance_set_t& msg);

/// The plan's message; reaches_goal comes from plan.reaches_goal. plan_seq numbers the planner's
/// plans; start_utime is the utime of the ROBOT_STATE the plan starts from (0: the path start).
rbcp_msgs::contact_plan_t ToContactPlanMsg(const ContactPlan& plan, int64_t utime, int64_t request_id,
                                           int64_t plan_seq = 0, int64_t start_utime = 0);

/// Throws InputError if counts disagree, a value is not finite or a moving leg is out of range.
ContactPlan FromContactPlanMsg(const rbcp_msgs::contact_plan_t& msg);

/// The message of a measured state with the controller's progress; utime = round(state.t * 1e6).
rbcp_msgs::robot_state_t ToRobotStateMsg(const RobotState& state, const ControllerProgress& progress = {});

/// Throws InputError if a value is not finite or the orientation is not a unit quaternion
/// (within 1e-3).
RobotState FromRobotStateMsg(const rbcp_msgs::robot_state_t& msg);

/// The controller's progress in a ROBOT_STATE. Throws InputError for a negative step count or a
/// wait that begins after the message's time.
ControllerProgress ProgressFromRobotStateMsg(const rbcp_msgs::robot_state_t& msg);

}  // namespace rbcp::transport
