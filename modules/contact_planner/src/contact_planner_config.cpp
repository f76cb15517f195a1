#include "rbcp/contact_planner/contact_planner_config.h"

#include <cmath>
#include <sstream>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

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
  fh.RejectUnknownKeys();

  c.torque_limit_fraction = map.Double("torque_limit_fraction");

  const YamlMap bs = map.Map("base_shift");
  c.base_shift.max_base_shift_m = bs.Double("max_base_shift_m");
  c.base_shift.shift_extra_margin_m = bs.Double("shift_extra_margin_m");
  c.base_shift.transit_checks = bs.Int("transit_checks");
  c.base_shift.height_step_m = bs.Double("height_step_m");
  c.base_shift.lateral_offsets_m = ReadArray<2>(bs, "lateral_offsets_m");
  c.base_shift.height_offsets_m = ReadArray<2>(bs, "height_offsets_m");
  bs.RejectUnknownKeys();

  const YamlMap bp = map.Map("base_pose");
  c.base_pose.follow_feet = bp.Bool("follow_feet");
  c.base_pose.height_offset_m = bp.Double("height_offset_m");
  c.base_pose.max_pitch_rad = bp.Double("max_pitch_rad");
  c.base_pose.max_roll_rad = bp.Double("max_roll_rad");
  bp.RejectUnknownKeys();

  c.goal_foot_tolerance_m = map.Double("goal_foot_tolerance_m");

  const YamlMap rt = map.Map("retry");
  c.retry.earlier_step_s = ReadArray<3>(rt, "earlier_step_s");
  c.retry.max_backtracks = rt.Int("max_backtracks");
  c.retry.max_steps_at_one_time = rt.Int("max_steps_at_one_time");
  c.retry.max_children_per_state = rt.Int("max_children_per_state");
  rt.RejectUnknownKeys();

  c.time_budget_s = map.Double("time_budget_s");
  map.RejectUnknownKeys();
  c.Validate(map.Where());
  return c;
}

ContactPlannerConfig ContactPlannerConfig::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

void ContactPlannerConfig::Validate(const std::string& where) const {
  auto fail = [&](const std::string& key, const std::string& expected, const std::string& got) {
    throw InputError(where + ": '" + key + "': expected " + expected + ", got " + got);
  };
  auto positive = [&](const std::string& key, double v) {
    if (!(std::isfinite(v) && v > 0.0)) fail(key, "a positive number", Num(v));
  };
  auto non_negative = [&](const std::string& key, double v) {
    if (!(std::isfinite(v) && v >= 0.0)) fail(key, "a non-negative number", Num(v));
  };
  positive("path_step_s", path_step_s);
  positive("step_time_resolution_s", step_time_resolution_s);
  non_negative("path_yaw_smoothing_s", path_yaw_smoothing_s);
  non_negative("gait_advance_s", gait_advance_s);
  if (step_time_resolution_s > path_step_s) {
    fail("step_time_resolution_s", "at most path_step_s (" + Num(path_step_s) + ")", Num(step_time_resolution_s));
  }
  positive("workspace.max_forward_m", workspace.max_forward_m);
  positive("workspace.max_backward_m", workspace.max_backward_m);
  positive("workspace.max_outward_m", workspace.max_outward_m);
  positive("workspace.max_inward_m", workspace.max_inward_m);
  positive("workspace.max_up_m", workspace.max_up_m);
  positive("workspace.max_down_m", workspace.max_down_m);
  positive("workspace.max_hip_distance_m", workspace.max_hip_distance_m);
  positive("foothold.query_distance_m", foothold.query_distance_m);
  non_negative("foothold.lead_time_s", foothold.lead_time_s);
  for (std::size_t i = 0; i < foothold.lead_time_factors.size(); ++i) {
    non_negative("foothold.lead_time_factors[" + std::to_string(i) + "]", foothold.lead_time_factors[i]);
  }
  positive("foothold.max_lead_yaw_rad", foothold.max_lead_yaw_rad);
  non_negative("foothold.static_weight", foothold.static_weight);
  non_negative("foothold.weight_x", foothold.weight_x);
  non_negative("foothold.weight_y", foothold.weight_y);
  non_negative("foothold.weight_z", foothold.weight_z);
  positive("foothold.dedup_cell_m", foothold.dedup_cell_m);
  non_negative("foothold.near_query_half_m", foothold.near_query_half_m);
  non_negative("foothold.min_foot_separation_m", foothold.min_foot_separation_m);
  if (foothold.max_stability_evaluations < 1) {
    fail("foothold.max_stability_evaluations", "an integer >= 1", std::to_string(foothold.max_stability_evaluations));
  }
  if (!(std::isfinite(torque_limit_fraction) && torque_limit_fraction > 0.0 && torque_limit_fraction <= 1.0)) {
    fail("torque_limit_fraction", "a number in (0, 1]", Num(torque_limit_fraction));
  }
  non_negative("base_shift.max_base_shift_m", base_shift.max_base_shift_m);
  non_negative("base_shift.shift_extra_margin_m", base_shift.shift_extra_margin_m);
  non_negative("base_shift.height_step_m", base_shift.height_step_m);
  if (base_shift.transit_checks < 0) {
    fail("base_shift.transit_checks", "an integer >= 0", std::to_string(base_shift.transit_checks));
  }
  for (std::size_t i = 0; i < 2; ++i) {
    const std::string n = "[" + std::to_string(i) + "]";
    if (!(std::abs(base_shift.lateral_offsets_m[i]) <= base_shift.max_base_shift_m)) {
      fail("base_shift.lateral_offsets_m" + n, "at most max_base_shift_m in magnitude", Num(base_shift.lateral_offsets_m[i]));
    }
    if (!std::isfinite(base_shift.height_offsets_m[i])) {
      fail("base_shift.height_offsets_m" + n, "a finite number", Num(base_shift.height_offsets_m[i]));
    }
  }
  if (!std::isfinite(base_pose.height_offset_m)) fail("base_pose.height_offset_m", "a finite number", Num(base_pose.height_offset_m));
  non_negative("base_pose.max_pitch_rad", base_pose.max_pitch_rad);
  non_negative("base_pose.max_roll_rad", base_pose.max_roll_rad);
  positive("goal_foot_tolerance_m", goal_foot_tolerance_m);
  for (std::size_t i = 0; i < retry.earlier_step_s.size(); ++i) {
    non_negative("retry.earlier_step_s[" + std::to_string(i) + "]", retry.earlier_step_s[i]);
  }
  if (retry.max_backtracks < 0) fail("retry.max_backtracks", "an integer >= 0", std::to_string(retry.max_backtracks));
  if (retry.max_children_per_state < 1) {
    fail("retry.max_children_per_state", "an integer >= 1", std::to_string(retry.max_children_per_state));
  }
  if (retry.max_steps_at_one_time < 1) {
    fail("retry.max_steps_at_one_time", "an integer >= 1", std::to_string(retry.max_steps_at_one_time));
  }
  positive("time_budget_s", time_budget_s);
}

}  // namespace rbcp
