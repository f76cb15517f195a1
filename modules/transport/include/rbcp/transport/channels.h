#pragma once
/// LCM channel names of the pipeline (the process graph is in the README).

namespace rbcp::channels {

inline constexpr const char* kTerrain = "TERRAIN";            ///< rbcp_msgs::terrain_mesh_t, from the simulator
inline constexpr const char* kAffordances = "AFFORDANCES";    ///< rbcp_msgs::affordance_set_t, from affordance_extractor
inline constexpr const char* kPlanRequest = "PLAN_REQUEST";   ///< rbcp_msgs::plan_request_t, from the operator or launcher
inline constexpr const char* kRobotState = "ROBOT_STATE";     ///< rbcp_msgs::robot_state_t, from the simulator
/// rbcp_msgs::controller_status_t, from the simulator (the onboard controller), beside every ROBOT_STATE
inline constexpr const char* kControllerStatus = "CONTROLLER_STATUS";
inline constexpr const char* kRootPath = "ROOT_PATH";         ///< rbcp_msgs::root_path_t, from root_planner
inline constexpr const char* kContactPlan = "CONTACT_PLAN";   ///< rbcp_msgs::contact_plan_t, from contact_planner
inline constexpr const char* kStatus = "STATUS";              ///< rbcp_msgs::process_status_t, from every process

}  // namespace rbcp::channels
