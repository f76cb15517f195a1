#pragma once
/// The JSON pieces the viewer reads (docs/json_schema.md), shared by scene_json (from a scenario),
/// run_log (from a recorded run) and live_bridge (from the running processes): terrain, contact
/// surfaces, root path, plans, robot states and process status.

#include <nlohmann/json.hpp>

#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::view {

/// {vertices: [[x, y, z], ...], triangles: [[i, j, k], ...]}
nlohmann::json TerrainJson(const TriangleMesh& mesh);
/// [{vertices, normal, area}, ...]
nlohmann::json SurfacesJson(const std::vector<AffordanceSurface>& surfaces);

/// TerrainJson of the message, with "scenario" (its scenario name). Throws InputError when invalid.
nlohmann::json TerrainJson(const rbcp_msgs::terrain_mesh_t& msg);
/// SurfacesJson of the message. Throws InputError when invalid.
nlohmann::json SurfacesJson(const rbcp_msgs::affordance_set_t& msg);
/// [{t, position, velocity, yaw}, ...], as plan_scenario's root_path.
nlohmann::json RootPathJson(const rbcp_msgs::root_path_t& msg);
/// {plan_seq, start_t, reaches_goal, states}; states as check_plan reads them. Throws InputError
/// for a malformed plan.
nlohmann::json ContactPlanJson(const rbcp_msgs::contact_plan_t& msg);
/// A trace sample (sim::TraceSampleToJson of the measured state) with the controller's progress
/// when known (CONTROLLER_STATUS): plan_seq, steps_done, awaiting_plan, phase, step (the trace
/// sample's own), base_error_m.
nlohmann::json RobotStateJson(const RobotModel& robot, const rbcp_msgs::robot_state_t& msg,
                              const rbcp_msgs::controller_status_t* controller = nullptr);
/// {t, process, state ("alive", "busy", "ok", "failed"), reason, compute_ms}
nlohmann::json StatusJson(const rbcp_msgs::process_status_t& msg);

}  // namespace rbcp::view
