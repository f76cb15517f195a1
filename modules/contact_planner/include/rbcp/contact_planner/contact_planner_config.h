#pragma once
/// Parameters of the contact planner (config/contact_planner.yaml). Stability thresholds
/// (friction, robustness, support margin) are those of the EquilibriumConfig given alongside.

#include <array>
#include <string>
#include <vector>

#include "rbcp/core/yaml_reader.h"

namespace rbcp {

/// Explicit step limits: the region, relative to a leg's reference foot position in the base
/// frame, in which a foot may stand. A stance foot that leaves it must step; a new foothold must
/// lie inside it.
struct FootWorkspace {
  double max_forward_m = 0.15;   ///< [m] foot ahead of the reference (base +x)
  double max_backward_m = 0.15;  ///< [m] foot behind it
  double max_outward_m = 0.10;   ///< [m] foot further from the body's centre line (|y| larger)
  double max_inward_m = 0.08;    ///< [m] foot closer to the centre line
  double max_up_m = 0.22;        ///< [m] foot above the reference height (base +z)
  double max_down_m = 0.12;      ///< [m] foot below it
  double max_hip_distance_m = 0.36;  ///< [m] horizontal (base x-y) distance from the HAA joint to the foot
};

/// Foothold generation and ranking.
struct FootholdConfig {
  double query_distance_m = 0.03;  ///< [m] database samples whose foot is this close to a surface
  double lead_time_s = 0.4;        ///< [s] target = reference foot at the path pose this far ahead
  /// Lead-time multipliers tried in turn when a step finds no foothold (the first is the nominal).
  std::array<double, 4> lead_time_factors = {1.0, 0.5, 0.0, 1.5};
  /// [rad] the target pose is taken earlier when the path turns more than this within the lead
  double max_lead_yaw_rad = 0.3;
  double static_weight = 0.05;     ///< weight of the offline score [0, 1] in the ranking
  double weight_x = 1.0;           ///< [1/m^2] target distance weights, target heading frame
  double weight_y = 3.0;
  double weight_z = 0.01;
  double dedup_cell_m = 0.01;      ///< [m] projected footholds in one grid cell count once
  double min_foot_separation_m = 0.10;  ///< [m] horizontal distance between any two footholds
  /// [m] a new foothold at least this far from the foot's previous one (shorter re-placements
  /// cost a step each and rarely unblock the search)
  double min_step_length_m = 0.05;
  int max_stability_evaluations = 80;   ///< candidates reaching the LP tests per step attempt
  /// [m] candidates are first taken from a square of this half-size around the target, then from
  /// the rest of the workspace (0: the whole workspace at once).
  double near_query_half_m = 0.1;
  /// A foothold whose swing cannot keep clear (StanceChecker::SwingClearance) rules out the
  /// candidates within this distance of it [m] (their swings rarely differ) ...
  double swing_failure_radius_m = 0.05;
  /// ... and after this many such footholds the step attempt gives up [-], >= 1.
  int max_swing_failures = 3;
};

/// Body shift that puts the CoM inside the three-foot support triangle of a swing.
struct BaseShiftConfig {
  double max_base_shift_m = 0.12;      ///< [m] horizontal offset of the base from the path
  double shift_extra_margin_m = 0.01;  ///< [m] aimed beyond the required support margin
  /// [-] fraction of a swing's horizontal shift the base keeps after touch-down, while the trunk
  /// advances to the next step (1: all of it, 0: back onto the path).
  double keep_fraction = 1.0;
  /// [m] a shift update that puts a stance foot out of reach is also tried with the base this
  /// much lower and higher (0: height kept).
  double height_step_m = 0.03;
  /// [m] lateral base offsets (path frame, + left) from which the shift search also starts when
  /// a step fails from the path itself.
  std::vector<double> lateral_offsets_m = {0.06, -0.06};
  /// [m] base height offsets (added to the stance height) also tried when a step fails.
  std::vector<double> height_offsets_m = {-0.04, -0.08};
};

/// How the base pose follows the stance.
struct BasePoseConfig {
  /// True: base height and roll/pitch follow the plane fitted through the four stance feet
  /// (height = plane height under the base + nominal base height + height_offset_m); false:
  /// level base at the root path's height.
  bool follow_feet = true;
  double height_offset_m = 0.0;  ///< [m]
  /// [-] share of the feet plane's pitch the base takes, in [0, 1] (0: level in pitch).
  double pitch_follow = 1.0;
  double max_pitch_rad = 0.35;   ///< [rad] |pitch| bound
  double max_roll_rad = 0.2;     ///< [rad] |roll| bound
};

/// Search bounds and retries.
struct RetryConfig {
  /// [s] a failed step is retried this much earlier on the path (before the failure time).
  std::array<double, 3> earlier_step_s = {0.1, 0.25, 0.5};
  int max_backtracks = 500;         ///< steps undone before giving up
  /// Leg evaluations (a foot kept at a base pose, a foothold candidate tested) a query may spend,
  /// over all its searches: the search's bound, so a plan does not depend on the machine's load
  /// (the time budget is only a safety limit).
  int max_evaluations = 2000000;
  /// Steps explored from one state: once this many of its children failed, the state itself is
  /// undone, so the search goes back further instead of trying every variant at a dead end.
  int max_children_per_state = 4;
  int max_steps_at_one_time = 6;    ///< steps without the trunk advancing along the path
  /// [s] when the search fails for want of footholds, it restarts with the crawl timing
  /// gait_advance_s replaced by each of these in turn (within max_evaluations and the time budget).
  std::vector<double> gait_advance_s = {0.3, 0.4};
  /// [-] after a crawl timing fails with base_shift.keep_fraction, it is tried again with each
  /// of these kept fractions of the swing shift before the next timing.
  std::vector<double> keep_fraction;
  /// [s] the other profiles are first tried from the state of the furthest search this much path
  /// time before its furthest point, keeping the steps up to there; then from the start (0: only
  /// from the start).
  double restart_back_s = 4.0;
  /// Leg evaluations one search (one profile) may make before the next profile is tried: a
  /// search that has not found its way by then rarely does.
  int max_search_evaluations = 400000;
  /// Searches run at once on as many threads: the next profiles are searched while the one
  /// before them runs, and the answer is taken in the order above, so the plan and the stats do
  /// not depend on it (1: one after another).
  int parallel_searches = 2;
};

/// Step merging after the search: a leg that steps twice keeps its first foothold until the
/// second step where the plan stays valid (see merge_steps.h in the planner's sources).
struct MergeConfig {
  bool enabled = true;
  /// [-] the workspace box of a foot kept longer or placed earlier by a merge, as a multiple of
  /// `workspace`'s box (the kinematic margins apply unscaled).
  double workspace_scale = 1.3;
};

struct ContactPlannerConfig {
  double path_step_s = 0.02;              ///< [s] root path discretisation of the keep phase
  double step_time_resolution_s = 0.002;  ///< [s] bisection resolution of a foot's last keepable time
  /// [s] half-width of the window over which the base heading is averaged along the path (0: the
  /// path heading); the window shrinks at the path ends so the start and goal headings are kept.
  double path_yaw_smoothing_s = 0.5;
  /// [s] crawl timing: the leg next in the crawl order (LH, LF, RH, RF) steps after the trunk has
  /// advanced at most this much path time since the last step (earlier if a foot must), so the
  /// feet stay near the middle of their workspace. 0: a leg steps only when a foot can no
  /// longer be kept.
  double gait_advance_s = 0.25;
  FootWorkspace workspace;
  FootholdConfig foothold;
  BaseShiftConfig base_shift;
  BasePoseConfig base_pose;
  double goal_foot_tolerance_m = 0.05;  ///< [m] feet farther from their goal position are re-placed
  /// [m] two contact surfaces this close are joined (a step bridges the gap); a path's end whose
  /// surfaces are joined to none of the start feet's is answered kGoalUnreachable at once.
  double max_surface_gap_m = 0.45;
  RetryConfig retry;
  MergeConfig merge;
  double time_budget_s = 5.0;           ///< [s] wall-clock budget of one planning query

  /// Reads every key strictly (missing or unknown keys, wrong types and out-of-range values throw
  /// InputError naming the key).
  static ContactPlannerConfig Load(const YamlMap& map);
  static ContactPlannerConfig LoadFile(const std::string& path);
  /// Throws InputError describing the first out-of-range value.
  void Validate(const std::string& where = "ContactPlannerConfig") const;
};

}  // namespace rbcp
