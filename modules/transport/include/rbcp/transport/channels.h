#pragma once
/// LCM channel names of the pipeline (the process graph is in the README).

namespace rbcp::channels {

/// rbcp_msgs::terrain_mesh_t: the terrain the planners plan on. From the simulator (its true
/// terrain, `--terrain ground_truth`) or from terrain_mapper (the mapped terrain, `--terrain perceived`).
inline constexpr const char* kTerrain = "TERRAIN";
/// rbcp_msgs::terrain_mesh_t, from the simulator when the planners plan on the mapped terrain:
/// the true terrain, for judging the map and for viewers (no planner listens).
inline constexpr const char* kTerrainTruth = "TERRAIN_TRUTH";
inline constexpr const char* kPointCloud = "POINT_CLOUD";     ///< rbcp_msgs::point_cloud_t, from the simulator's depth sensors
inline constexpr const char* kElevationMap = "ELEVATION_MAP"; ///< rbcp_msgs::elevation_map_t, from terrain_mapper
inline constexpr const char* kAffordances = "AFFORDANCES";    ///< rbcp_msgs::affordance_set_t, from affordance_extractor
inline constexpr const char* kPlanRequest = "PLAN_REQUEST";   ///< rbcp_msgs::plan_request_t, from the operator or launcher
inline constexpr const char* kRobotState = "ROBOT_STATE";     ///< rbcp_msgs::robot_state_t, from the simulator
/// rbcp_msgs::controller_status_t, from the simulator (the onboard controller), beside every ROBOT_STATE
inline constexpr const char* kControllerStatus = "CONTROLLER_STATUS";
inline constexpr const char* kRootPath = "ROOT_PATH";         ///< rbcp_msgs::root_path_t, from root_planner
inline constexpr const char* kContactPlan = "CONTACT_PLAN";   ///< rbcp_msgs::contact_plan_t, from contact_planner
inline constexpr const char* kStatus = "STATUS";              ///< rbcp_msgs::process_status_t, from every process

}  // namespace rbcp::channels
