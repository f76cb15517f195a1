#pragma once
/// Parameters of the contact planner (config/contact_planner.yaml). Stability thresholds
/// (friction, robustness) are those of the EquilibriumConfig given alongside, the stance rules
/// (support margin, torques, clearances, the swing path) those of the StanceConfig. Frames: base
/// frame x forward, y left, z up; the path frame is the path's heading (yaw) frame.

#include <array>
#include <string>
#include <vector>

#include "rbcp/core/config_fields.h"
#include "rbcp/core/yaml_reader.h"

namespace rbcp {

/// Explicit step limits: the region, relative to a leg's reference foot position in the base
/// frame (RobotModel::ReferenceFootPosition), in which a foot may stand. A stance foot that leaves
/// it must step; a new foothold must lie inside it. The robot's kinematic margins apply as well.
struct FootWorkspace {
  double max_forward_m = 0.25;
  double max_backward_m = 0.25;
  double max_outward_m = 0.15;
  double max_inward_m = 0.15;
  double max_up_m = 0.22;
  double max_down_m = 0.12;
  double max_hip_distance_m = 0.35;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("max_forward_m", &max_forward_m, "m", bounds::Positive(), "foot ahead of its reference position (base +x)");
    v->Visit("max_backward_m", &max_backward_m, "m", bounds::Positive(), "foot behind it");
    v->Visit("max_outward_m", &max_outward_m, "m", bounds::Positive(),
             "foot further from the body's centre line than its reference (|y| larger)");
    v->Visit("max_inward_m", &max_inward_m, "m", bounds::Positive(), "foot closer to the centre line");
    v->Visit("max_up_m", &max_up_m, "m", bounds::Positive(), "foot above its reference height (base +z)");
    v->Visit("max_down_m", &max_down_m, "m", bounds::Positive(), "foot below it");
    v->Visit("max_hip_distance_m", &max_hip_distance_m, "m", bounds::Positive(),
             "horizontal (base x-y) distance from the HAA joint to the foot");
  }
};

/// Foothold generation and ranking: limb-database samples near a contact surface, ranked by
/// static_weight * offline score - (w_x dx^2 + w_y dy^2 + w_z dz^2), (dx, dy, dz) the offset from
/// the target in the target's heading frame.
struct FootholdConfig {
  double query_distance_m = 0.03;
  double lead_time_s = 0.6;
  std::array<double, 4> lead_time_factors = {1.0, 0.5, 0.0, 1.5};
  double max_lead_yaw_rad = 0.3;
  double static_weight = 0.05;
  double weight_x = 1.0;
  double weight_y = 3.0;
  double weight_z = 0.01;
  double dedup_cell_m = 0.01;
  double min_foot_separation_m = 0.10;
  double min_step_length_m = 0.05;
  int max_stability_evaluations = 80;
  double near_query_half_m = 0.1;
  double swing_failure_radius_m = 0.05;
  int max_swing_failures = 3;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("query_distance_m", &query_distance_m, "m", bounds::Positive(),
             "database samples whose foot lies this close to a contact surface are candidates");
    v->Visit("lead_time_s", &lead_time_s, "s", bounds::NonNegative(),
             "target: the leg's reference foot position at the path pose this far ahead");
    v->Visit("lead_time_factors", &lead_time_factors, "", bounds::NonNegative(),
             "the lead time is multiplied by each in turn when a step finds no foothold");
    v->Visit("max_lead_yaw_rad", &max_lead_yaw_rad, "rad", bounds::Positive(),
             "the target pose is taken earlier when the path heading turns more than this within the lead time");
    v->Visit("static_weight", &static_weight, "", bounds::NonNegative(), "weight of the offline score [0, 1]");
    v->Visit("weight_x", &weight_x, "1/m^2", bounds::NonNegative(), "weight of the target distance along x");
    v->Visit("weight_y", &weight_y, "1/m^2", bounds::NonNegative(), "... along y");
    v->Visit("weight_z", &weight_z, "1/m^2", bounds::NonNegative(), "... along z");
    v->Visit("dedup_cell_m", &dedup_cell_m, "m", bounds::Positive(),
             "candidates projected into one grid cell of this size are one (the best scored)");
    v->Visit("min_foot_separation_m", &min_foot_separation_m, "m", bounds::NonNegative(),
             "horizontal distance kept between any two footholds");
    v->Visit("min_step_length_m", &min_step_length_m, "m", bounds::NonNegative(),
             "a new foothold lies at least this far from the foot's previous one");
    v->Visit("max_stability_evaluations", &max_stability_evaluations, "", bounds::AtLeast(1),
             "candidates that reach the equilibrium tests (LPs) per step attempt");
    v->Visit("near_query_half_m", &near_query_half_m, "m", bounds::NonNegative(),
             "candidates come first from a square of this half-size around the target, then from the rest of "
             "the workspace (0: the whole workspace at once)");
    v->Visit("swing_failure_radius_m", &swing_failure_radius_m, "m", bounds::NonNegative(),
             "a foothold whose swing cannot keep clear rules out the candidates this close to it ...");
    v->Visit("max_swing_failures", &max_swing_failures, "", bounds::AtLeast(1),
             "... and after this many such footholds the step attempt gives up");
  }
};

/// Body shift that puts the CoM inside the three-foot support triangle of a swing.
struct BaseShiftConfig {
  double max_base_shift_m = 0.16;
  double shift_extra_margin_m = 0.01;
  double keep_fraction = 1.0;
  double height_step_m = 0.03;
  std::vector<double> lateral_offsets_m = {-0.12, 0.12};
  std::vector<double> height_offsets_m = {0.04, -0.06, -0.12};

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("max_base_shift_m", &max_base_shift_m, "m", bounds::NonNegative(),
             "largest horizontal offset of the base from the path");
    v->Visit("shift_extra_margin_m", &shift_extra_margin_m, "m", bounds::NonNegative(),
             "the shift aims this much deeper into the support triangle than the support margin needs");
    v->Visit("keep_fraction", &keep_fraction, "", bounds::Closed(0, 1),
             "fraction of a swing's horizontal shift the base keeps after touch-down (1: all, 0: back onto the path)");
    v->Visit("height_step_m", &height_step_m, "m", bounds::NonNegative(),
             "a shift that puts a stance foot out of reach is also tried with the base this much lower and higher");
    v->Visit("lateral_offsets_m", &lateral_offsets_m, "m",
             bounds::Any().AtLeast(-max_base_shift_m, "-max_base_shift_m").AtMost(max_base_shift_m, "max_base_shift_m"),
             "when a step fails from the current shift, the shift search also starts from these lateral offsets "
             "(path frame, + left)");
    v->Visit("height_offsets_m", &height_offsets_m, "m", bounds::Any(),
             "... and with the base raised or lowered by these");
  }
};

/// How the base pose follows the stance.
struct BasePoseConfig {
  bool follow_feet = true;
  double height_offset_m = 0.0;
  double pitch_follow = 0.6;
  double max_pitch_rad = 0.35;
  double max_roll_rad = 0.2;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("follow_feet", &follow_feet,
             "the base height and roll follow the plane through the four stance feet (false: a level base at the "
             "path's height)");
    v->Visit("height_offset_m", &height_offset_m, "m", bounds::Any(),
             "base height above that plane beyond the nominal base height");
    v->Visit("pitch_follow", &pitch_follow, "", bounds::Closed(0, 1), "share of the plane's pitch the base takes");
    v->Visit("max_pitch_rad", &max_pitch_rad, "rad", bounds::NonNegative(), "|pitch| bound");
    v->Visit("max_roll_rad", &max_roll_rad, "rad", bounds::NonNegative(), "|roll| bound");
  }
};

/// Search bounds and retries.
struct RetryConfig {
  std::array<double, 3> earlier_step_s = {0.1, 0.25, 0.5};
  int max_backtracks = 100;
  int max_evaluations = 3000000;
  int max_children_per_state = 4;
  int max_steps_at_one_time = 6;
  std::vector<double> gait_advance_s = {0.3, 0.4, 0.25, 0.45};
  std::vector<double> keep_fraction;
  double restart_back_s = 4.0;
  int max_search_evaluations = 400000;
  int parallel_searches = 2;
  int walk_searches = 3;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("earlier_step_s", &earlier_step_s, "s", bounds::NonNegative(),
             "a failed step is retried this much path time before the failure");
    v->Visit("max_backtracks", &max_backtracks, "", bounds::AtLeast(0), "steps undone before a search gives up");
    v->Visit("max_evaluations", &max_evaluations, "", bounds::AtLeast(1),
             "leg evaluations (a foot kept at a base pose, a foothold candidate tested) a query may make over all "
             "its searches");
    v->Visit("max_children_per_state", &max_children_per_state, "", bounds::AtLeast(1),
             "once this many steps from one state have failed, that state's own step is undone too");
    v->Visit("max_steps_at_one_time", &max_steps_at_one_time, "", bounds::AtLeast(1),
             "steps allowed without the trunk advancing along the path");
    v->Visit("gait_advance_s", &gait_advance_s, "s", bounds::NonNegative(),
             "crawl timings the search restarts with, in turn, when one fails");
    v->Visit("keep_fraction", &keep_fraction, "", bounds::Closed(0, 1),
             "each crawl timing is also tried with base_shift.keep_fraction replaced by each of these");
    v->Visit("restart_back_s", &restart_back_s, "s", bounds::NonNegative(),
             "the next timings start first from the failed search's state this much path time before the furthest "
             "point it reached, then from the start (0: from the start only)");
    v->Visit("max_search_evaluations", &max_search_evaluations, "", bounds::AtLeast(1),
             "leg evaluations one search (one timing) may make before the next is tried");
    v->Visit("parallel_searches", &parallel_searches, "", bounds::Closed(1, 16),
             "searches run at once, on as many threads; the plan does not depend on it");
    v->Visit("walk_searches", &walk_searches, "", bounds::AtLeast(0),
             "a plan whose dynamic walk puts a leg on the terrain or a foot out of reach is searched for again at "
             "most this many times, each search also without the step blamed for the first such failure of the best "
             "plan so far (collisions first); the plan with the fewest such steps, then the fewest failing steps, is "
             "the answer");
  }
};

/// Step merging after the search: a leg that steps twice keeps its first foothold until the
/// second step where the plan stays valid (see merge_steps.h in the planner's sources).
struct MergeConfig {
  bool enabled = true;
  double workspace_scale = 1.3;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("enabled", &enabled, "steps are merged");
    v->Visit("workspace_scale", &workspace_scale, "", bounds::Closed(1, 4),
             "the workspace box of a foot kept longer or placed earlier by a merge, as a multiple of `workspace`");
  }
};

struct ContactPlannerConfig {
  double path_step_s = 0.02;
  double step_time_resolution_s = 0.002;
  double path_yaw_smoothing_s = 0.5;
  double gait_advance_s = 0.35;
  FootWorkspace workspace;
  FootholdConfig foothold;
  BaseShiftConfig base_shift;
  BasePoseConfig base_pose;
  double goal_foot_tolerance_m = 0.05;
  double max_surface_gap_m = 0.45;
  RetryConfig retry;
  MergeConfig merge;
  double time_budget_s = 10.0;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("path_step_s", &path_step_s, "s", bounds::Positive(),
             "the trunk advances along the root path in steps of this much path time while the feet are kept");
    v->Visit("step_time_resolution_s", &step_time_resolution_s, "s",
             bounds::Positive().AtMost(path_step_s, "path_step_s"),
             "resolution of the bisection for the time a foot can no longer be kept");
    v->Visit("path_yaw_smoothing_s", &path_yaw_smoothing_s, "s", bounds::NonNegative(),
             "the base heading is the path heading averaged over +- this much path time (0: the path heading)");
    v->Visit("gait_advance_s", &gait_advance_s, "s", bounds::NonNegative(),
             "crawl timing: the next leg in the crawl order LH, LF, RH, RF steps once the trunk has advanced this "
             "much path time since the previous step (0: only when a foot must)");
    v->Visit("workspace", &workspace, "explicit step limits around each foot's reference position");
    v->Visit("foothold", &foothold, "foothold generation and ranking");
    v->Visit("base_shift", &base_shift, "the body shift of a swing");
    v->Visit("base_pose", &base_pose, "how the base pose follows the stance");
    v->Visit("goal_foot_tolerance_m", &goal_foot_tolerance_m, "m", bounds::Positive(),
             "at the path's end, feet farther than this from their reference position are re-placed");
    v->Visit("max_surface_gap_m", &max_surface_gap_m, "m", bounds::Positive(),
             "two contact surfaces this close are joined; a goal no chain of joined surfaces reaches is answered "
             "goal_unreachable at once");
    v->Visit("retry", &retry, "search bounds and retries");
    v->Visit("merge", &merge, "step merging after the search");
    v->Visit("time_budget_s", &time_budget_s, "s", bounds::Positive(),
             "wall-clock safety limit of one query (its end is a timeout)");
  }

  /// Reads every key strictly (missing or unknown keys, wrong types and out-of-range values throw
  /// InputError naming the key).
  static ContactPlannerConfig Load(const YamlMap& map) { return LoadConfig<ContactPlannerConfig>(map); }
  static ContactPlannerConfig LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }
  /// Throws InputError describing the first out-of-range value.
  void Validate(const std::string& where = "ContactPlannerConfig") const { ValidateConfig(*this, where); }
};

}  // namespace rbcp
