#pragma once
/// Contact planning along a root path (RB-PRM, Geisert et al. 2019, with explicit step limits,
/// backtracking and executability checks).
///
/// The trunk follows the root path while the four feet are kept in place by leg inverse
/// kinematics. A foot that can no longer be kept (no IK solution, joint bounds, collision, or
/// outside the explicit workspace of ContactPlannerConfig::workspace) makes its leg step; when
/// several fail together the one furthest outside its workspace (the most stretched) steps first,
/// at the last path time at which all four could still be kept. With gait_advance_s > 0 the legs
/// also step in crawl order (LH, LF, RH, RF) before that: the next leg steps once the trunk has
/// advanced gait_advance_s of path time since the previous step, so the feet stay near the middle
/// of their workspace; the forced steps above remain the fallback. The new foothold comes from the
/// limb database: samples whose foot lies near the contact surfaces around a target (the leg's
/// reference foot at the path pose lead_time_s ahead), ranked by distance to the target plus the
/// offline score, projected onto the surface (closest point of the eroded polygon) and solved
/// exactly by analytic IK. The first candidate that passes every test is taken:
///  * joint bounds, workspace, minimum distance to the other feet;
///  * no collision with the terrain (whole robot, stance feet allowed to touch) nor with itself;
///  * static equilibrium of the new four-foot stance with the configured robustness (LP over
///    linearised friction cones);
///  * the stance rules the controller walks by (StanceChecker, config/stance.yaml): the torques of
///    the four-foot stances and the three-foot stance of the swing, with the controller's force
///    distribution, below the ceiling; the CoM's ground projection support_margin_m inside the
///    triangle of the three stance feet with the swing leg both at lift-off and at touch-down; the
///    base's shift to the step pose (reach, support, clearance, torques); and, last, the swing
///    path to the foothold clear of the terrain and the body, which the plan then carries.
/// To meet the last test the base may be shifted horizontally off the path (at most
/// max_base_shift_m); base_shift.keep_fraction of it is kept while the trunk advances to the
/// next step. The shift search of a step
/// starts from the current shift (the body stays where it is); when the step fails from there it
/// is retried from the path pose, from lateral offsets and with the base raised or lowered
/// (base_shift.lateral_offsets_m, height_offsets_m).
/// The path gives the base x and y, and its heading averaged over path_yaw_smoothing_s gives the
/// base yaw (the start and goal headings are kept); with base_pose.follow_feet the base height,
/// roll and pitch follow the plane through the stance feet (so the trunk pitches on stairs),
/// otherwise the base is level at the path height. A state's base pose follows the feet before
/// its step.
///
/// Between consecutive states the base moves in a straight line (position and yaw interpolated)
/// with the previous state's four feet in place; intermediate poses are checked for kinematics
/// and support. After a hind leg, the fore leg on the same side is tried first (crawl order). A
/// step with no valid foothold is retried with other target lead times and shift starts, earlier
/// on the path, with another leg, and then by undoing earlier steps (bounded); after that the
/// search is run again with each of the crawl timings of retry.gait_advance_s (and kept shares
/// of retry.keep_fraction), first from the state the failed search had reached
/// retry.restart_back_s of path time before its furthest point, then from the start; only then
/// the planner fails, naming the path time and the leg. When a stance leg hits the terrain at
/// lift-off (a riser, a wall), that leg is re-placed first.
///
/// At the path end every foot farther than goal_foot_tolerance_m from its reference position at
/// the final pose is re-placed next to it, and the last state's base is at the path end (up to
/// the body shift of its swing).
///
/// Step merging (merge.enabled) then shortens the plan found: a leg that steps A -> B and later
/// B -> C stands on A until it steps A -> C, or steps A -> C at once, wherever every state this
/// changes passes the search's own checks again (the body shift of each swing in between is
/// searched again where the old one no longer fits). The search moves a leg when the crawl timing
/// or its workspace box says so; the steps the other legs take next often leave it room to stay.
///
/// Output states: base pose, 12 joints, four feet (contact point on the surface and the surface
/// normal). Joints put every foot contact point exactly on its contact (forward kinematics).
/// Consecutive states differ by exactly one leg's contact.
///
/// Deterministic: the same inputs give the same plan. The wall clock is read only to report the
/// planning time and to enforce the time budget.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/contact_planner/contact_planner_config.h"
#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/contact_plan.h"
#include "rbcp/core/root_path_sample.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/equilibrium/config.h"
#include "rbcp/root_planner/root_path.h"
#include "rbcp/stance/stance_config.h"

namespace rbcp {

class RobotModel;
class LimbDatabase;

/// Why a query ended.
enum class ContactPlanStatus {
  kOk,              ///< plan found (to the goal, or the requested number of steps)
  kInvalidInput,    ///< empty path, no terrain set, invalid current state
  kNoStartStance,   ///< no valid standing stance at the path start
  kNoFoothold,      ///< a step found no valid foothold after every retry
  /// No chain of contact surfaces, each within max_surface_gap_m of the next, joins the start
  /// feet's surfaces to those in the feet's reach at the path's end (answered before any step).
  kGoalUnreachable,
  kTimeout,         ///< time budget exhausted
};

/// Every status, in declaration order.
inline constexpr ContactPlanStatus kContactPlanStatuses[] = {
    ContactPlanStatus::kOk,         ContactPlanStatus::kInvalidInput,     ContactPlanStatus::kNoStartStance,
    ContactPlanStatus::kNoFoothold, ContactPlanStatus::kGoalUnreachable, ContactPlanStatus::kTimeout};

/// "ok", "invalid_input", "no_start_stance", "no_foothold", "goal_unreachable", "timeout".
std::string ToString(ContactPlanStatus status);

/// Whether the query failed along its root path, so that another path (the next guide,
/// RootPlannerConfig::guide_retries) may succeed: no foothold, or out of budget. Bad input, no
/// start stance and an unreachable goal fail along any path.
bool FailedAlongPath(ContactPlanStatus status);

/// Work done by one query.
struct ContactPlanStats {
  int keep_checks = 0;           ///< keep-in-place tests of a leg at a base pose
  int step_attempts = 0;         ///< (leg, time, lead) combinations searched for a foothold
  int candidates = 0;            ///< database candidates returned by the queries
  int candidates_evaluated = 0;  ///< distinct projected footholds tested
  int stability_evaluations = 0; ///< footholds that reached the equilibrium LPs
  int swing_checks = 0;          ///< swing paths planned and checked (footholds that passed every other test)
  int backtracks = 0;            ///< steps undone
  int steps_merged = 0;          ///< steps removed from the found plan by step merging
  int walk_steps_slowed = 0;     ///< steps the dynamic walk's timing slowed (TimeDynamicWalk)
  int walk_steps_failing = 0;    ///< steps whose dynamic walk still fails its check at that timing
  int walk_searches = 0;         ///< searches repeated without a step whose dynamic walk failed its check

  /// Leg evaluations (keep checks and candidates evaluated): the work that
  /// ContactPlannerConfig::retry.max_evaluations bounds.
  long Evaluations() const { return static_cast<long>(keep_checks) + static_cast<long>(candidates_evaluated); }

  /// Field by field: the work of two parts of a query added, or the work between two counts.
  ContactPlanStats& operator+=(const ContactPlanStats& o) {
    for (int ContactPlanStats::*counter : kCounters) this->*counter += o.*counter;
    return *this;
  }
  ContactPlanStats operator-(const ContactPlanStats& o) const {
    ContactPlanStats d = *this;
    for (int ContactPlanStats::*counter : kCounters) d.*counter -= o.*counter;
    return d;
  }

 private:
  /// Every counter above: a new one is added here too.
  static constexpr int ContactPlanStats::*kCounters[] = {
      &ContactPlanStats::keep_checks,   &ContactPlanStats::step_attempts,         &ContactPlanStats::candidates,
      &ContactPlanStats::candidates_evaluated, &ContactPlanStats::stability_evaluations, &ContactPlanStats::swing_checks,
      &ContactPlanStats::backtracks,    &ContactPlanStats::steps_merged,          &ContactPlanStats::walk_steps_slowed,
      &ContactPlanStats::walk_steps_failing,   &ContactPlanStats::walk_searches};
};

struct ContactPlanResult {
  bool ok = false;
  ContactPlanStatus status = ContactPlanStatus::kInvalidInput;
  std::string reason;            ///< empty when ok; otherwise what failed, where and for which leg
  double planning_time_s = 0.0;  ///< wall-clock time of the query [s]
  int steps = 0;                 ///< plan.states.size() - 1 when ok
  bool reached_goal = false;     ///< the plan ends at the path end with the feet at their goal
  double failure_time_s = -1.0;  ///< path time [s] of the step that failed (-1 if none)
  int failure_leg = -1;          ///< Index(Leg) of the leg that could not step (-1 if none)
  ContactPlan plan;
  ContactPlanStats stats;
};

/// A stance the planner made (StandingStance, MeasuredStance), or why there is none.
struct StanceResult {
  /// kOk with a state; kInvalidInput (no terrain set, a value not finite), kNoStartStance (no
  /// valid stance there), kTimeout (the time budget ended the search for one).
  ContactPlanStatus status = ContactPlanStatus::kInvalidInput;
  std::string reason;  ///< when not ok: what failed, naming the leg
  std::optional<WholeBodyState> state;

  bool ok() const { return status == ContactPlanStatus::kOk; }
};

/// Plans contact sequences for one robot over one terrain at a time. Holds the equilibrium LP
/// workspace and the terrain collision structure, so queries are not const and an instance
/// must not be shared between threads. The robot model and limb database must outlive it.
class ContactPlanner {
 public:
  /// `stance`: the stance rules every stance and step must satisfy, the controller's (with the
  /// equilibrium configuration's friction). Throws InputError for an invalid configuration.
  ContactPlanner(const RobotModel& robot, const LimbDatabase& database, const EquilibriumConfig& equilibrium,
                 const ContactPlannerConfig& config, const StanceConfig& stance);
  ~ContactPlanner();
  ContactPlanner(ContactPlanner&&) noexcept;
  ContactPlanner& operator=(ContactPlanner&&) noexcept;
  ContactPlanner(const ContactPlanner&) = delete;
  ContactPlanner& operator=(const ContactPlanner&) = delete;

  /// Sets the world: the terrain mesh (collision) and its contact surfaces (footholds). Builds
  /// the collision structure. Throws InputError for an invalid mesh.
  void SetTerrain(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces);

  /// Plans from a standing stance at the path start to the path end. The path is given by its
  /// samples (times increasing from 0 or any start time; positions and yaws are interpolated
  /// linearly between them).
  ContactPlanResult Plan(const std::vector<RootPathSample>& path);
  /// Same, on a RootPath sampled every 0.01 s.
  ContactPlanResult Plan(const RootPath& path);

  /// Receding horizon: plans at most max_steps steps from `current` (a whole-body state with
  /// four feet in contact) along `remaining_path` (whose first sample should be near the current
  /// base). current.moving_leg, the leg that stepped last (-1: none known), continues the crawl:
  /// the next leg in the crawl order steps first unless another must, and that leg itself steps
  /// again only once the trunk has advanced along the path (unless no plan is found otherwise).
  /// The plan's first state is
  /// `current` with its joints recomputed by IK at its base pose (moving_leg -1). ok with
  /// reached_goal false when max_steps steps were planned before the path end.
  ContactPlanResult PlanHorizon(const WholeBodyState& current, const std::vector<RootPathSample>& remaining_path,
                                int max_steps);

  /// The standing stance at a base pose: for each leg, the best foothold near the reference foot
  /// position below the hip; kNoStartStance when none is valid. Requires SetTerrain().
  StanceResult StandingStance(const Eigen::Vector3d& base_position_W, double yaw);

  /// Times every step of `plan` for the dynamic walk and checks the walk it implies
  /// (TimeDynamicWalk with the planner's stance rules and terrain); adds the steps it slowed and
  /// those still failing to *stats (optional). Every plan the planner returns is timed so; a plan
  /// assembled from pieces is timed again with this, its first `keep_steps` steps keeping their
  /// durations (TimeDynamicWalk). Throws InputError for a kept step without timing.
  void TimeWalk(ContactPlan* plan, ContactPlanStats* stats = nullptr, int keep_steps = 0) const;

  /// The stance of a measured state, for PlanHorizon: the base pose as given and each foot's
  /// contact point (world frame, e.g. by forward kinematics of the measured joints) moved to the
  /// closest point of the nearest contact surface, with that surface's normal. kNoStartStance
  /// when a foot is farther than max_offset_m from every surface. Requires SetTerrain().
  StanceResult MeasuredStance(const Eigen::Vector3d& base_position_W, const Eigen::Vector3d& base_rpy,
                              const std::array<Eigen::Vector3d, kNumLegs>& feet_W, double max_offset_m) const;

  /// `plan` with the steps removed that step merging can remove (ContactPlannerConfig::merge):
  /// a leg that steps A -> B and later B -> C stands on A until it steps to C, or steps to C at
  /// once, wherever every state this changes stays valid under the planner's checks. The first
  /// state and each leg's last foothold are kept. Plan() and PlanHorizon() already merge when
  /// merge.enabled; this is for a plan found with it off, or by other means. The result holds the
  /// merged plan and, in stats.steps_merged, the number of steps removed; kInvalidInput with the
  /// reason without SetTerrain(), for a state with a non-finite number, or for a plan whose states
  /// are not one step apart (see check_plan's "one_leg").
  ContactPlanResult MergeSteps(const ContactPlan& plan);

  /// `plan` walked from `start` instead of its first state: start has that state's base pose
  /// and footholds but for one foot (e.g. one that touched down a few cm beside its foothold).
  /// That foot stands where start has it until its leg steps again; the states this changes are
  /// checked and made valid as step merging checks them (base poses kept where valid, else the
  /// swing's body shift searched again), swings are attached again and the walk is timed with
  /// every step's duration kept. kInvalidInput without SetTerrain() or for an empty plan;
  /// kNoFoothold with the reason when start differs otherwise, when a changed state is not
  /// valid, or when the dynamic walk fails its check at more steps than plan's does.
  ContactPlanResult FromStart(const ContactPlan& plan, const WholeBodyState& start);

  /// `plan`, made on another terrain (a mapped terrain that has changed since), on this one:
  /// every foothold (where it is) within `max_offset_m` of a contact surface, every state checked
  /// with its own base pose as step merging checks a state, swings attached again and the walk
  /// timed with every step's duration kept. kInvalidInput without SetTerrain() or for
  /// an empty plan; kNoFoothold with the reason when a foothold has no surface that near, a state
  /// is not valid, or the dynamic walk fails its check at more steps than plan's does.
  ContactPlanResult OnThisTerrain(const ContactPlan& plan, double max_offset_m);

  const ContactPlannerConfig& Config() const;
  const EquilibriumConfig& EquilibriumParameters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbcp
