#pragma once
/// The contact planner process: ROOT_PATH, ROBOT_STATE, TERRAIN and AFFORDANCES in; CONTACT_PLAN
/// and STATUS out. Callbacks only keep the latest messages; Step() does the work.
///
/// Every new ROOT_PATH is planned once, on the newest terrain and contact surfaces:
///  * horizon_steps = 0: the whole path, from a standing stance at the path start;
///  * horizon_steps = K > 0 (receding horizon): at most K steps from where the robot is. The
///    current state is the planner's standing stance at the measured base x, y and yaw of the
///    latest ROBOT_STATE, at the height of the path sample nearest to it (the standing height the
///    root planner found over the terrain, so the body's bobbing during a swing does not move the
///    stance); the remaining path starts at that sample. Without any ROBOT_STATE yet, the stance
///    is taken at the path start. The loop is closed by the root planner: each replanned
///    ROOT_PATH (PLAN_REQUEST with use_start = false) gives the next horizon.
/// A path with no point, non-finite values, non-increasing times, points more than 0.5 m beyond
/// the terrain's horizontal bounds or a start with no terrain below is rejected with FAILED and
/// the reason (the trunk may pass over gaps); so is a measured state too far from the path.

#include <lcm/lcm-cpp.hpp>

#include <optional>
#include <string>
#include <vector>

#include "rbcp/contact_planner/contact_planner.h"
#include "rbcp/core/root_path_sample.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/nodes/world_input.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::nodes {

struct ContactPlannerNodeOptions {
  std::string root_path_channel = channels::kRootPath;
  std::string robot_state_channel = channels::kRobotState;
  std::string terrain_channel = channels::kTerrain;
  std::string affordances_channel = channels::kAffordances;
  std::string contact_plan_channel = channels::kContactPlan;
  std::string status_channel = channels::kStatus;
  /// 0: plan the whole path; K > 0: at most K steps from the measured robot state.
  int horizon_steps = 0;
  /// Horizon mode: largest horizontal distance from the measured base to the path [m].
  double max_path_offset_m = 0.5;
};

class ContactPlannerNode {
 public:
  static constexpr const char* kProcessName = "contact_planner";

  /// The robot and the database must outlive the node. Throws InputError for an invalid
  /// configuration.
  ContactPlannerNode(lcm::LCM& lcm, const RobotModel& robot, const LimbDatabase& database,
                     const EquilibriumConfig& equilibrium, const ContactPlannerConfig& config,
                     ContactPlannerNodeOptions options = {});

  /// Takes the newest inputs; when a root path is pending and the terrain and its surfaces are
  /// known, plans and publishes CONTACT_PLAN (or FAILED with the reason on STATUS). Returns true
  /// if it planned or rejected an input.
  bool Step();
  void Heartbeat();

  /// Logs to stderr which inputs it waits for and when it plans (and the status lines).
  void set_verbose(bool verbose);
  transport::StatusReporter& status() { return status_; }
  /// The latest answer (not ok when the latest path failed); empty before the first plan.
  const std::optional<ContactPlanResult>& last_result() const { return last_result_; }

 private:
  /// Takes new terrain / surfaces / path; returns a reason if an input was rejected.
  std::optional<std::string> TakeInputs();
  void Plan(const rbcp_msgs::root_path_t& msg);
  /// The path of a message, or the reason it is rejected.
  std::optional<std::string> ToSamples(const rbcp_msgs::root_path_t& msg, std::vector<RootPathSample>* samples) const;
  void LogWaiting();
  int64_t Now() const;

  lcm::LCM& lcm_;
  ContactPlannerNodeOptions options_;
  ContactPlanner planner_;
  transport::LatestMessage<rbcp_msgs::root_path_t> root_path_;
  transport::LatestMessage<rbcp_msgs::robot_state_t> robot_state_;
  WorldInput world_;
  transport::StatusReporter status_;

  Eigen::Vector2d terrain_min_xy_ = Eigen::Vector2d::Zero();  ///< horizontal bounds of the terrain [m]
  Eigen::Vector2d terrain_max_xy_ = Eigen::Vector2d::Zero();
  bool world_set_ = false;      ///< the planner holds the current terrain and surfaces
  std::optional<rbcp_msgs::root_path_t> pending_;
  std::optional<ContactPlanResult> last_result_;
  int64_t latest_utime_ = 0;
  bool verbose_ = true;
  std::string logged_waiting_;
};

/// The limb database of config_dir (limb_database.yaml, robots/anymal_b.*): read from its disk
/// cache, or built and cached (some seconds). With `log`, says on stderr which, how long it took
/// and how large it is. Throws InputError for bad files.
LimbDatabase LoadLimbDatabase(const RobotModel& robot, const std::string& config_dir, bool log);

}  // namespace rbcp::nodes
