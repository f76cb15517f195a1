#include "rbcp/contact_planner/contact_planner_config.h"

#include <cmath>

#include "rbcp/core/config_checks.h"

namespace rbcp {
namespace {

template <std::size_t N>
std::array<double, N> ReadArray(const YamlMap& map, const std::string& key) {
  const Eigen::VectorXd v = map.Vector(key, static_cast<int>(N));
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = v[static_cast<int>(i)];
  return out;
}

}  // namespace

ContactPlannerConfig ContactPlannerConfig::Load(const YamlMap& map) {
  ContactPlannerConfig c;
  c.path_step_s = map.Double("path_step_s");
  c.step_time_resolution_s = map.Double("step_time_resolution_s");
  c.path_yaw_smoothing_s = map.Double("path_yaw_smoothing_s");
  c.gait_advance_s = map.Double("gait_advance_s");

  const YamlMap ws = map.Map("workspace");
  c.workspace.max_forward_m = ws.Double("max_forward_m");
  c.workspace.max_backward_m = ws.Double("max_backward_m");
  c.workspace.max_outward_m = ws.Double("max_outward_m");
  c.workspace.max_inward_m = ws.Double("max_inward_m");
  c.workspace.max_up_m = ws.Double("max_up_m");
  c.workspace.max_down_m = ws.Double("max_down_m");
  c.workspace.max_hip_distance_m = ws.Double("max_hip_distance_m");
  ws.RejectUnknownKeys();

  const YamlMap fh = map.Map("foothold");
  c.foothold.query_distance_m = fh.Double("query_distance_m");
  c.foothold.lead_time_s = fh.Double("lead_time_s");
  c.foothold.lead_time_factors = ReadArray<4>(fh, "lead_time_factors");
  c.foothold.max_lead_yaw_rad = fh.Double("max_lead_yaw_rad");
  c.foothold.static_weight = fh.Double("static_weight");
  c.foothold.weight_x = fh.Double("weight_x");
  c.foothold.weight_y = fh.Double("weight_y");
  c.foothold.weight_z = fh.Double("weight_z");
  c.foothold.dedup_cell_m = fh.Double("dedup_cell_m");
  c.foothold.min_foot_separation_m = fh.Double("min_foot_separation_m");
  c.foothold.max_stability_evaluations = fh.Int("max_stability_evaluations");
  c.foothold.near_query_half_m = fh.Double("near_query_half_m");
  c.foothold.swing_failure_radius_m = fh.Double("swing_failure_radius_m");
  c.foothold.max_swing_failures = fh.Int("max_swing_failures");
  c.foothold.min_step_length_m = fh.Double("min_step_length_m");
  fh.RejectUnknownKeys();


  const YamlMap bs = map.Map("base_shift");
  c.base_shift.max_base_shift_m = bs.Double("max_base_shift_m");
  c.base_shift.shift_extra_margin_m = bs.Double("shift_extra_margin_m");
  c.base_shift.keep_fraction = bs.Double("keep_fraction");
  c.base_shift.height_step_m = bs.Double("height_step_m");
  c.base_shift.lateral_offsets_m = bs.Numbers("lateral_offsets_m");
  c.base_shift.height_offsets_m = bs.Numbers("height_offsets_m");
  bs.RejectUnknownKeys();

  const YamlMap bp = map.Map("base_pose");
  c.base_pose.follow_feet = bp.Bool("follow_feet");
  c.base_pose.height_offset_m = bp.Double("height_offset_m");
  c.base_pose.pitch_follow = bp.Double("pitch_follow");
  c.base_pose.max_pitch_rad = bp.Double("max_pitch_rad");
  c.base_pose.max_roll_rad = bp.Double("max_roll_rad");
  bp.RejectUnknownKeys();

  c.goal_foot_tolerance_m = map.Double("goal_foot_tolerance_m");
  c.max_surface_gap_m = map.Double("max_surface_gap_m");

  const YamlMap rt = map.Map("retry");
  c.retry.earlier_step_s = ReadArray<3>(rt, "earlier_step_s");
  c.retry.max_backtracks = rt.Int("max_backtracks");
  c.retry.max_evaluations = rt.Int("max_evaluations");
  c.retry.max_steps_at_one_time = rt.Int("max_steps_at_one_time");
  c.retry.max_children_per_state = rt.Int("max_children_per_state");
  c.retry.gait_advance_s = rt.Numbers("gait_advance_s");
  c.retry.keep_fraction = rt.Numbers("keep_fraction");
  c.retry.restart_back_s = rt.Double("restart_back_s");
  c.retry.max_search_evaluations = rt.Int("max_search_evaluations");
  c.retry.parallel_searches = rt.Int("parallel_searches");
  rt.RejectUnknownKeys();

  const YamlMap mg = map.Map("merge");
  c.merge.enabled = mg.Bool("enabled");
  c.merge.workspace_scale = mg.Double("workspace_scale");
  mg.RejectUnknownKeys();

  c.time_budget_s = map.Double("time_budget_s");
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

ContactPlannerConfig ContactPlannerConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

void ContactPlannerConfig::Validate(const std::string& where) const {
  const ConfigChecks check(where);
  check.Positive("path_step_s", path_step_s);
  check.Positive("step_time_resolution_s", step_time_resolution_s);
  check.NonNegative("path_yaw_smoothing_s", path_yaw_smoothing_s);
  check.NonNegative("gait_advance_s", gait_advance_s);
  if (step_time_resolution_s > path_step_s) {
    check.Fail("step_time_resolution_s", "at most path_step_s (" + ConfigNumber(path_step_s) + ")",
               ConfigNumber(step_time_resolution_s));
  }
  check.Positive("workspace.max_forward_m", workspace.max_forward_m);
  check.Positive("workspace.max_backward_m", workspace.max_backward_m);
  check.Positive("workspace.max_outward_m", workspace.max_outward_m);
  check.Positive("workspace.max_inward_m", workspace.max_inward_m);
  check.Positive("workspace.max_up_m", workspace.max_up_m);
  check.Positive("workspace.max_down_m", workspace.max_down_m);
  check.Positive("workspace.max_hip_distance_m", workspace.max_hip_distance_m);
  check.Positive("foothold.query_distance_m", foothold.query_distance_m);
  check.NonNegative("foothold.lead_time_s", foothold.lead_time_s);
  for (std::size_t i = 0; i < foothold.lead_time_factors.size(); ++i) {
    check.NonNegative("foothold.lead_time_factors[" + std::to_string(i) + "]", foothold.lead_time_factors[i]);
  }
  check.Positive("foothold.max_lead_yaw_rad", foothold.max_lead_yaw_rad);
  check.NonNegative("foothold.static_weight", foothold.static_weight);
  check.NonNegative("foothold.weight_x", foothold.weight_x);
  check.NonNegative("foothold.weight_y", foothold.weight_y);
  check.NonNegative("foothold.weight_z", foothold.weight_z);
  check.Positive("foothold.dedup_cell_m", foothold.dedup_cell_m);
  check.NonNegative("foothold.near_query_half_m", foothold.near_query_half_m);
  check.NonNegative("foothold.swing_failure_radius_m", foothold.swing_failure_radius_m);
  check.AtLeast("foothold.max_swing_failures", foothold.max_swing_failures, 1);
  check.NonNegative("foothold.min_step_length_m", foothold.min_step_length_m);
  check.NonNegative("foothold.min_foot_separation_m", foothold.min_foot_separation_m);
  check.AtLeast("foothold.max_stability_evaluations", foothold.max_stability_evaluations, 1);
  check.NonNegative("base_shift.max_base_shift_m", base_shift.max_base_shift_m);
  check.NonNegative("base_shift.shift_extra_margin_m", base_shift.shift_extra_margin_m);
  check.NonNegative("base_shift.height_step_m", base_shift.height_step_m);
  check.InRange("base_shift.keep_fraction", base_shift.keep_fraction, 0.0, 1.0);
  for (std::size_t i = 0; i < base_shift.lateral_offsets_m.size(); ++i) {
    if (!(std::abs(base_shift.lateral_offsets_m[i]) <= base_shift.max_base_shift_m)) {
      check.Fail("base_shift.lateral_offsets_m[" + std::to_string(i) + "]", "at most max_base_shift_m in magnitude",
                 ConfigNumber(base_shift.lateral_offsets_m[i]));
    }
  }
  for (std::size_t i = 0; i < base_shift.height_offsets_m.size(); ++i) {
    check.Finite("base_shift.height_offsets_m[" + std::to_string(i) + "]", base_shift.height_offsets_m[i]);
  }
  check.Finite("base_pose.height_offset_m", base_pose.height_offset_m);
  check.InRange("base_pose.pitch_follow", base_pose.pitch_follow, 0.0, 1.0);
  check.NonNegative("base_pose.max_pitch_rad", base_pose.max_pitch_rad);
  check.NonNegative("base_pose.max_roll_rad", base_pose.max_roll_rad);
  check.Positive("goal_foot_tolerance_m", goal_foot_tolerance_m);
  check.Positive("max_surface_gap_m", max_surface_gap_m);
  for (std::size_t i = 0; i < retry.earlier_step_s.size(); ++i) {
    check.NonNegative("retry.earlier_step_s[" + std::to_string(i) + "]", retry.earlier_step_s[i]);
  }
  check.AtLeast("retry.max_backtracks", retry.max_backtracks, 0);
  check.AtLeast("retry.max_evaluations", retry.max_evaluations, 1);
  check.AtLeast("retry.max_children_per_state", retry.max_children_per_state, 1);
  check.AtLeast("retry.max_steps_at_one_time", retry.max_steps_at_one_time, 1);
  for (std::size_t i = 0; i < retry.gait_advance_s.size(); ++i) {
    check.NonNegative("retry.gait_advance_s[" + std::to_string(i) + "]", retry.gait_advance_s[i]);
  }
  check.NonNegative("retry.restart_back_s", retry.restart_back_s);
  check.AtLeast("retry.max_search_evaluations", retry.max_search_evaluations, 1);
  check.InRange("retry.parallel_searches", retry.parallel_searches, 1, 16);
  for (std::size_t i = 0; i < retry.keep_fraction.size(); ++i) {
    check.InRange("retry.keep_fraction[" + std::to_string(i) + "]", retry.keep_fraction[i], 0.0, 1.0);
  }
  check.InRange("merge.workspace_scale", merge.workspace_scale, 1.0, 4.0);
  check.Positive("time_budget_s", time_budget_s);
}

}  // namespace rbcp
