#pragma once
/// The contact planner process: ROOT_PATH, ROBOT_STATE, TERRAIN and AFFORDANCES in; CONTACT_PLAN
/// and STATUS out. Callbacks only keep the latest messages; Step() does the work.
///
/// Two modes, on the newest terrain and contact surfaces:
///  * horizon_steps = 0: every new ROOT_PATH is planned once, whole, from a standing stance at
///    the path start;
///  * horizon_steps = K > 0 (receding horizon, the onboard loop): the node keeps the newest
///    ROOT_PATH and answers every wait of the robot's controller at a step boundary (a
///    CONTROLLER_STATUS with awaiting_plan, each awaiting_since once, and the ROBOT_STATE of that
///    wait) with at most K steps from the measured stance (searched lookahead_steps further, by
///    default to the goal, so the K steps do not walk into a dead end that only shows later):
///    the measured base pose, and the feet where forward kinematics of the
///    measured joints puts them, each moved onto the nearest contact surface (at most
///    max_foot_offset_m away); a foot within foothold_match_m of a foothold of the same leg in the
///    previous plan stands there (the plan's own numbers: consecutive plans then join exactly,
///    and only a foot that really slid is moved). The remaining path starts at the path sample nearest to the
///    measured base (position, and heading at 0.3 m/rad), never behind the previous one.
///    CONTACT_PLAN carries plan_seq, start_utime (that state's utime) and reaches_goal; STATUS
///    answers with input_utime = that state's utime.
/// A path with no point, non-finite values, non-increasing times, points more than 0.5 m beyond
/// the terrain's horizontal bounds or a start with no terrain below is rejected with FAILED and
/// the reason (the trunk may pass over gaps); so is a measured state too far from the path, or
/// with a foot off every surface.

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <functional>
#include <future>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/contact_planner/contact_planner.h"
#include "rbcp/core/root_path_sample.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/nodes/rejected_input.h"
#include "rbcp/nodes/world_input.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/sim_clock.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::nodes {

struct ContactPlannerNodeOptions {
  std::string root_path_channel = channels::kRootPath;
  std::string robot_state_channel = channels::kRobotState;
  std::string controller_status_channel = channels::kControllerStatus;
  std::string terrain_channel = channels::kTerrain;
  std::string affordances_channel = channels::kAffordances;
  std::string contact_plan_channel = channels::kContactPlan;
  std::string status_channel = channels::kStatus;
  /// 0: plan the whole path; K > 0: at most K steps from the measured robot state.
  int horizon_steps = 0;
  /// Horizon mode: steps searched beyond the K published ones (a horizon whose continuation is
  /// known to exist). The default reaches the goal on any path: the K steps are the start of a
  /// whole plan. A shorter look-ahead plans faster but can walk the robot into a stance from
  /// which no plan leads on (on the DARPA mesh, 8 steps ended before the centre block, and 8 of
  /// 20 runs stood in such a stance).
  int lookahead_steps = 1000;
  /// Horizon mode, along a path short of the goal (partial_map): steps searched beyond the K
  /// published at most, so that the search need not end in a standing stance at the edge of what
  /// the map shows (the path's end is no goal; the next map carries the path on). Along a path
  /// to the goal that finds no plan, the look-ahead of a second search along the path as far as
  /// the map shows terrain under the feet: the way may cross cells not seen yet (in the shadow
  /// of a block).
  int partial_lookahead_steps = 4;
  /// Horizon mode: largest horizontal distance from the measured base to the path [m].
  double max_path_offset_m = 0.5;
  /// Horizon mode: largest distance from a measured foot to the contact surface it stands on [m].
  double max_foot_offset_m = 0.05;
  /// Horizon mode: a measured foot this close to a foothold of the previous plan stands there [m].
  double foothold_match_m = 0.02;
  /// Horizon mode: once a plan is out, plan the next one while the robot walks its first step,
  /// from the stance that step leads to; at the next boundary it is taken at once if the robot
  /// stands there (same footholds, base within base_match_m and base_match_rad).
  bool plan_ahead = true;
  /// Horizon mode, plan_ahead: at a step boundary, wait for the new search made ahead to end.
  /// Then the plan depends only on the state the robot waits in (the loop with the world standing
  /// still while the robot waits). false, for a robot on the wall clock (`--realtime`): a search
  /// made ahead that has not ended by the boundary is not waited for; the earlier search goes on
  /// (when the robot stands where its continuation starts) and the new search's answer is dropped.
  bool wait_for_search_ahead = true;
  /// Horizon mode: the terrain is a map that grows as the robot walks (terrain_mapper, which
  /// sends a map for every wait at the wait's time): a wait is answered only on a TERRAIN of its
  /// time or later (utime >= awaiting_since), never on an older map, so that the plan depends on
  /// the clouds up to the wait and not on when the map arrived.
  bool partial_map = false;
  /// partial_map: a plan made ahead on an earlier map is taken on the map of the wait when it
  /// holds there (ContactPlanner::OnThisTerrain: every foothold within this of a contact surface,
  /// every state valid) [m]
  double map_foothold_offset_m = 0.02;
  /// Horizon mode, plan_ahead: the earlier search goes on instead of a new plan whose K steps get
  /// the trunk less far, while it holds horizon_steps + reuse_margin_steps steps after the next
  /// one (or reaches the goal).
  int reuse_margin_steps = 4;
  /// Horizon mode: the controller walks the plan; with every foot on the plan's footholds, a base
  /// within base_match_m of the reference the controller tracks (CONTROLLER_STATUS base_error)
  /// and within base_match_rad (roll, pitch, yaw) of the orientation the plan put it in stands in
  /// the plan's pose: what it measures off that pose is the controller's tracking error, or in the
  /// dynamic walk the sway of the CoM around the plan's base poses (often 8 to 15 cm at a step
  /// boundary), along the trajectory the planner checked. The next plan starts from the planned
  /// pose.
  double base_match_m = 0.08;    ///< [m]
  double base_match_rad = 0.05;  ///< [rad] roll, pitch and yaw
  /// Horizon mode: while the robot still waits at the stance the last plan answered, that plan
  /// is sent again this often [s, wall clock], so a lost message costs a resend, not the
  /// simulator's whole wait. Whole-path mode: a repeat of the path answered last gets its plan
  /// again, at most this often. 0: never.
  double resend_period_s = 1.0;
  /// A ROOT_PATH lasting longer than this is rejected [s] (the search walks the path in time).
  double max_path_duration_s = 3600.0;
};

/// Horizon mode's choice of the plan made ahead between a new search and `continuation`, the
/// steps of the earlier search after the one being walked: true when the earlier search goes on,
/// because the new search failed (and the continuation holds a step), or because the
/// continuation reaches the goal or holds k + margin steps and its state k lies further along the
/// path (progress: path sample index of a state's base) than the new plan's.
bool KeepEarlierSearch(const ContactPlan& continuation, const ContactPlanResult& fresh, int k, int margin,
                       const std::function<std::size_t(const WholeBodyState&)>& progress);

/// How a measured stance differs from the one a plan made ahead starts from: the first
/// difference found (the footholds, then the base's position, then its orientation).
struct StanceDeviation {
  enum class Kind {
    kFoothold,         ///< `leg` stands `amount` m from its planned foothold
    kBasePosition,     ///< the base is `amount` m off the controller's reference (beyond base_match_m)
    kBaseOrientation,  ///< the base's roll, pitch or yaw is `amount` rad off (beyond base_match_rad)
  };
  Kind kind = Kind::kFoothold;
  Leg leg = Leg::kLF;   ///< kFoothold
  double amount = 0.0;  ///< [m] or [rad]

  /// E.g. "LF stands 0.0123 m from its planned foothold".
  std::string Describe() const;
};

/// Why the answer to a wait is not the plan made ahead.
struct PlanAheadMissed {
  enum class Kind {
    kNone,           ///< no plan was made ahead
    kOtherPlan,      ///< the robot walks another plan than the one planned ahead from
    kStanceDeviates, ///< the robot does not stand where the plan made ahead starts (deviation)
    kFailed,         ///< the plan made ahead failed
    kMapChanged,     ///< made on an earlier map, it does not hold on the map of the wait
  };
  Kind kind = Kind::kNone;
  std::optional<StanceDeviation> deviation;  ///< kStanceDeviates

  std::string Describe() const;
};

class ContactPlannerNode {
 public:
  static constexpr const char* kProcessName = "contact_planner";

  /// The robot and the database must outlive the node. Throws InputError for an invalid
  /// configuration.
  ContactPlannerNode(lcm::LCM& lcm, const RobotModel& robot, const LimbDatabase& database,
                     const EquilibriumConfig& equilibrium, const ContactPlannerConfig& config,
                     const StanceConfig& stance, ContactPlannerNodeOptions options = {});
  /// Waits for a search made ahead that still runs.
  ~ContactPlannerNode();
  ContactPlannerNode(const ContactPlannerNode&) = delete;
  ContactPlannerNode& operator=(const ContactPlannerNode&) = delete;

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
  /// A plan made ahead, while the robot walks the first step of a plan, from the stance that
  /// step leads to.
  struct PlanMadeAhead {
    int64_t after_plan_seq = 0;  ///< the plan whose first step leads to `expected`
    WholeBodyState expected;
    std::size_t progress = 0;    ///< path progress at `expected`
    ContactPlanResult result;
  };
  /// The plan made ahead while it is being made: the earlier search's continuation after the
  /// published plan's first step, its first `kept` steps committed, and the new search from the
  /// stance they lead to (on ahead_planner_, in search_worker_) when `running`.
  struct SearchAhead {
    PlanMadeAhead next;  ///< everything but the result
    ContactPlan continuation;
    int kept = 0;
    bool running = false;
  };
  /// What the search made ahead returns: its result, or the error it threw.
  struct SearchAheadAnswer {
    std::optional<ContactPlanResult> result;
    std::string error;
  };
  /// Steps a search plans at most: K and the look-ahead (partial_lookahead_steps along a path
  /// short of the goal).
  int SearchSteps() const;
  int WholeSearchSteps() const;    ///< K and lookahead_steps
  int PartialSearchSteps() const;  ///< K and partial_lookahead_steps (at most lookahead_steps)
  /// partial_map: whether the plan made ahead, searched on an earlier map, holds on this one
  /// (ContactPlanner::OnThisTerrain); if so `ahead` takes that plan.
  bool HoldsOnThisMap(PlanMadeAhead& ahead);

  /// Takes new terrain / surfaces / path; returns why an input was rejected, if one was.
  std::optional<RejectedInput> TakeInputs();
  void Plan(const rbcp_msgs::root_path_t& msg);
  /// A path is waiting and was planned on the terrain the planner holds.
  bool PendingPathFitsTheWorld() const;
  /// The path taken last, again: same request, terrain and samples.
  /// The path being followed, for the same request (on whichever terrain).
  bool SamePath(const rbcp_msgs::root_path_t& msg, const std::vector<RootPathSample>& samples) const;
  bool IsRepeat(const rbcp_msgs::root_path_t& msg, const std::vector<RootPathSample>& samples) const;
  /// Horizon mode: keeps a new path as the one to follow.
  void TakePath(const rbcp_msgs::root_path_t& msg);
  /// Horizon mode: plans from the measured stance of a waiting robot (or takes the plan made
  /// ahead when the robot stands where it starts), publishes it, then plans ahead.
  void Replan(const rbcp_msgs::robot_state_t& state, const rbcp_msgs::controller_status_t& controller);
  /// Horizon mode: the state of the last plan the robot should have reached after the steps it
  /// walked of it (controller.steps_done), or nullptr when it walks another plan.
  const WholeBodyState* ReachedPlanState(const rbcp_msgs::controller_status_t& controller) const;
  /// Horizon mode: a measured foot within foothold_match_m of a foothold of the last plan stands
  /// there (the one of the state the robot should have reached, else the nearest); on the
  /// reached state's footholds, a base on the controller's reference (base_match_m) and within
  /// base_match_rad of the reached state's orientation stands in its pose too, and the crawl goes
  /// on from its moving leg. Returns the number of feet on footholds of the last plan.
  int SnapToLastPlan(const rbcp_msgs::controller_status_t& controller, WholeBodyState* stance) const;
  /// Horizon mode: why the plan made ahead, `ahead`, does not answer the wait of a robot in
  /// `stance` whose controller reports `controller`; nullopt when it does.
  std::optional<PlanAheadMissed> WhyNotPlannedAhead(const std::optional<PlanMadeAhead>& ahead,
                                                    const WholeBodyState& stance,
                                                    const rbcp_msgs::controller_status_t& controller) const;
  /// Horizon mode: whether the plan made ahead answers a robot whose stance differs from the
  /// one it starts from in one foot only (`missed`: a foot that touched down beside its foothold)
  /// once that foot stands where it is (ContactPlanner::FromStart); then ahead.result is that
  /// plan.
  bool HoldsWithOneFootOff(PlanMadeAhead& ahead, const PlanAheadMissed& missed, const WholeBodyState& stance,
                           const rbcp_msgs::controller_status_t& controller);
  /// Horizon mode: publishes the first horizon_steps steps of *last_result_ (FAILED when it
  /// failed) as the answer to the robot's wait, then plans ahead.
  void PublishHorizon(const rbcp_msgs::robot_state_t& state, const rbcp_msgs::controller_status_t& controller);
  /// Sends the last CONTACT_PLAN again when resend_period_s has passed since it went out; true
  /// if it did.
  bool ResendAnswerIfDue();
  /// Horizon mode: sends the last plan again when the robot still waits for it after
  /// resend_period_s; true if it did.
  bool ResendIfStillAwaited(const rbcp_msgs::controller_status_t& state);
  /// Horizon mode: starts the piece that follows the published plan's first step: its next
  /// `steps_committed` steps kept (CONTROLLER_STATUS: the controller's motion prepares for them),
  /// then a new search (K steps and the look-ahead deep) from the stance they lead to, on
  /// ahead_planner_ in the background, or the earlier search's continuation.
  void PlanAhead(int steps_committed);
  /// Horizon mode, at a step boundary: makes plan_made_ahead_ of the search started by PlanAhead
  /// (waiting for it to end, unless !wait_for_search_ahead): the new search's plan after the kept
  /// steps, or the earlier search's continuation (KeepEarlierSearch).
  void FinishPlanAhead();
  /// plan_made_ahead_ = the earlier search's continuation; `how` is logged.
  void TakeEarlierSearch(SearchAhead search, const std::string& how);
  /// Forgets the plan made ahead (a search still running goes on; its answer is dropped).
  void DropPlanAhead();
  /// Waits for the search made ahead, if one runs (its answer is dropped unless FinishPlanAhead
  /// takes it).
  void WaitForSearchWorker();
  bool SearchWorkerBusy() const;
  /// Path sample nearest to a base pose, not behind path_progress_; its horizontal distance in
  /// *offset_xy.
  std::size_t PathProgress(const Eigen::Vector3d& base_W, double yaw, double* offset_xy) const;
  /// How a measured stance differs from the expected one (another foothold, the base beyond
  /// base_match_m of the controller's reference, base_error_m, or beyond base_match_rad of the
  /// expected orientation), or nullopt when it is that stance.
  std::optional<StanceDeviation> Deviation(const WholeBodyState& measured, const WholeBodyState& expected,
                                           double base_error_m) const;
  /// The path of a message into *samples, or why it is rejected.
  std::optional<RejectedInput> ToSamples(const rbcp_msgs::root_path_t& msg, std::vector<RootPathSample>* samples) const;
  void LogWaiting();
  int64_t Now() const;

  lcm::LCM& lcm_;
  const RobotModel& robot_;
  ContactPlannerNodeOptions options_;
  ContactPlanner planner_;
  /// The searches made ahead run on their own planner (a planner serves one thread), in
  /// search_worker_, while the node answers the robot.
  ContactPlanner ahead_planner_;
  transport::LatestMessage<rbcp_msgs::root_path_t> root_path_;
  transport::LatestMessage<rbcp_msgs::robot_state_t> robot_state_;
  transport::LatestMessage<rbcp_msgs::controller_status_t> controller_;
  WorldInput world_;
  transport::StatusReporter status_;

  Eigen::Vector2d terrain_min_xy_ = Eigen::Vector2d::Zero();  ///< horizontal bounds of the terrain [m]
  Eigen::Vector2d terrain_max_xy_ = Eigen::Vector2d::Zero();
  bool world_set_ = false;      ///< the planner holds the current terrain and surfaces
  std::optional<rbcp_msgs::root_path_t> pending_;
  // Horizon mode: the path followed, its request, how far along it the robot is, the wait answered last.
  std::vector<RootPathSample> path_;
  int64_t path_request_id_ = 0;
  int64_t path_utime_ = 0;  ///< ROOT_PATH.utime of the path followed
  /// The terrain the path followed was planned on: while the world's is another, the path is stale
  /// and no answer goes out until a path on the world's terrain comes.
  int64_t path_terrain_id_ = 0;
  bool path_reaches_goal_ = true;  ///< the path ends at the goal (root_path_t.reaches_goal)
  std::size_t path_progress_ = 0;
  bool logged_stale_ = false;
  std::optional<int64_t> answered_since_;
  /// The last CONTACT_PLAN published and when it went out (wall clock).
  std::optional<rbcp_msgs::contact_plan_t> answer_;
  std::chrono::steady_clock::time_point answer_wall_;
  std::optional<ContactPlan> last_plan_;
  std::optional<PlanMadeAhead> plan_made_ahead_;
  int64_t plan_ahead_terrain_id_ = 0;  ///< the terrain the plan made ahead is searched on
  std::optional<SearchAhead> search_ahead_;
  std::future<SearchAheadAnswer> search_worker_;  ///< declared after ahead_planner_, which it uses
  ContactPlan searched_;  ///< the whole last plan searched or continued (K steps and the look-ahead)
  int64_t plan_seq_ = 0;
  int32_t plan_start_steps_ = 0;  ///< ROBOT_STATE.steps_done when the last plan went out
  std::optional<ContactPlanResult> last_result_;
  transport::SimClock clock_;  ///< the simulated time heard of (message utimes)
  bool verbose_ = true;
  std::string logged_waiting_;
};

/// The limb database of config_dir (limb_database.yaml, robots/anymal_b.*): read from its disk
/// cache, or built and cached (some seconds). With `log`, says on stderr which, how long it took
/// and how large it is. Throws InputError for bad files.
LimbDatabase LoadLimbDatabase(const RobotModel& robot, const std::string& config_dir, bool log);

}  // namespace rbcp::nodes
