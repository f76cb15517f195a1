#pragma once
/// Conversions between LCM messages and the libraries' Eigen types. Messages coming in are
/// untrusted: conversions from a message validate it and throw rbcp::InputError with the reason.

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/core/root_path_sample.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/robot/robot_state.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::transport {

/// Positions in a message farther than this from the origin along any axis are rejected [m]: no
/// terrain of the robot's spans that far, and beyond it distances lose their centimetres.
inline constexpr double kMaxCoordinate_m = 1.0e5;
/// A message's unit vectors and quaternions may differ this much from norm 1.
inline constexpr double kUnitTolerance = 1e-3;

/// True when the n values of a message array are all finite.
inline bool AllFinite(const double* v, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

/// A terrain's identity: a 64-bit hash of its vertices and triangles, never 0. Two terrains of
/// the same content have the same id, whoever sent them and whenever; surfaces, root paths and
/// contact plans carry the id of the terrain they were made from, so that no process pairs
/// inputs made from different terrains.
int64_t TerrainId(const TriangleMesh& mesh);

/// The terrain's message, with terrain_id = TerrainId(mesh).
rbcp_msgs::terrain_mesh_t ToTerrainMsg(const TriangleMesh& mesh, int64_t utime, const std::string& scenario_name);

/// Throws InputError if the counts disagree with the arrays, a vertex is not finite or beyond
/// kMaxCoordinate_m, an index is out of range, a triangle is degenerate or the terrain_id is not
/// the content's.
TriangleMesh FromTerrainMsg(const rbcp_msgs::terrain_mesh_t& msg);

/// The surfaces extracted from the terrain `terrain_id`, sent at `utime`.
rbcp_msgs::affordance_set_t ToAffordanceMsg(const std::vector<AffordanceSurface>& surfaces, int64_t utime,
                                            int64_t terrain_id);

/// Throws InputError if counts disagree, a value is not finite, a vertex is beyond
/// kMaxCoordinate_m, a polygon has < 3 vertices, a normal is not a unit vector or an area is
/// negative.
std::vector<AffordanceSurface> FromAffordanceMsg(const rbcp_msgs::affordance_set_t& msg);

/// The plan's message; reaches_goal comes from plan.reaches_goal. terrain_id is the terrain it was
/// planned on; plan_seq numbers the planner's plans; start_utime is the utime of the ROBOT_STATE
/// the plan starts from (0: the path start).
rbcp_msgs::contact_plan_t ToContactPlanMsg(const ContactPlan& plan, int64_t utime, int64_t request_id,
                                           int64_t terrain_id, int64_t plan_seq = 0, int64_t start_utime = 0);

/// Throws InputError if counts disagree, a value is not finite, a position is beyond
/// kMaxCoordinate_m, a foot normal is not a unit vector or a moving leg is out of range.
ContactPlan FromContactPlanMsg(const rbcp_msgs::contact_plan_t& msg);

/// The message of a measured state; utime = round(state.t * 1e6).
rbcp_msgs::robot_state_t ToRobotStateMsg(const RobotState& state);

/// Throws InputError if a value is not finite, the base is beyond kMaxCoordinate_m or the
/// orientation is not a unit quaternion (within kUnitTolerance).
RobotState FromRobotStateMsg(const rbcp_msgs::robot_state_t& msg);

/// The controller's progress as CONTROLLER_STATUS carries it at `utime` [us].
rbcp_msgs::controller_status_t ToControllerStatusMsg(int64_t utime, const ControllerProgress& progress);

/// Throws InputError for a negative step count or step, a wait that begins after the message's
/// time, a swing leg out of range, a non-finite error or margin, or a phase name over 32 bytes.
ControllerProgress FromControllerStatusMsg(const rbcp_msgs::controller_status_t& msg);

/// The samples of a root path (yaw from the orientations, rest_yaw = yaw). Throws InputError if
/// the count disagrees, the path is empty, a value is not finite, a position is beyond
/// kMaxCoordinate_m, an orientation is not a unit quaternion, the times do not increase or the
/// path lasts longer than max_duration_s.
std::vector<RootPathSample> FromRootPathMsg(const rbcp_msgs::root_path_t& msg, double max_duration_s);

/// Why a plan request cannot be planned: the field at fault and what is wrong with it.
struct PlanRequestProblem {
  enum class Kind {
    kGoal,        ///< the goal position is not finite or beyond kMaxCoordinate_m
    kGoalYaw,     ///< the goal yaw is not finite
    kStart,       ///< with use_start: the start position, as kGoal
    kStartYaw,    ///< with use_start: the start yaw is not finite
    kTimeBudget,  ///< the time budget is not finite or exceeds the limit
  };
  Kind kind;
  std::string detail;  ///< what is wrong with the field, e.g. "is not finite"

  /// E.g. "plan request: goal is not finite".
  std::string Describe() const;
};

/// Why a plan request cannot be planned, or nullopt when it can: a goal (or, with use_start, a
/// start) not finite or beyond kMaxCoordinate_m, or a time budget that is not finite or exceeds
/// max_time_budget_s.
std::optional<PlanRequestProblem> CheckPlanRequest(const rbcp_msgs::plan_request_t& msg, double max_time_budget_s);

}  // namespace rbcp::transport
