#pragma once
/// The clock of the dynamic walk (stance.yaml, section dynamic_walk): how long four feet stay down
/// between two swings, how fast a foot swings, and the ZMP preview that moves the CoM. The contact
/// planner times a plan's steps with it and checks the walk it implies; the controller walks that
/// timing (walking_pattern.h).

#include "rbcp/core/config_fields.h"
#include "rbcp/stance/zmp_preview.h"

namespace rbcp {

/// How long the four-foot phases of a walk last and where its ZMP reference keeps (part of
/// DynamicWalkConfig); the swings' own durations come with each plan (GaitTiming).
struct GaitPhases {
  double start_s = 0.0;
  double four_foot_s = 0.0;
  double zmp_speed_mps = 0.0;
  double base_rise_mps = 0.0;
  double base_turn_radps = 0.0;
  double final_s = 0.0;
  double zmp_margin_m = 0.0;
  double load_s = 0.06;
  double unload_s = 0.1;

  template <class Visitor>
  void Serialize(Visitor* v) {
    const Bounds duration = bounds::Positive().AtMost(60.0);
    v->Visit("start_s", &start_s, "s", duration, "four feet down from rest before the first swing of a plan");
    v->Visit("four_foot_s", &four_foot_s, "s", duration,
             "four feet down between two swings, at least: the ZMP moves to the next support triangle, the leg "
             "that touched down loads and the next one unloads");
    v->Visit("zmp_speed_mps", &zmp_speed_mps, "m/s", bounds::Positive(),
             "four feet stay down as long as the ZMP reference takes to reach the next support triangle at this speed");
    v->Visit("base_rise_mps", &base_rise_mps, "m/s", bounds::Positive(),
             "and as long as the base takes to reach the next step's height at this peak speed (a min-jerk move)");
    v->Visit("base_turn_radps", &base_turn_radps, "rad/s", bounds::Positive(),
             "and its attitude at this peak rate (a leg swings with the base at the height and attitude it was "
             "planned at)");
    v->Visit("final_s", &final_s, "s", duration,
             "after a plan's last step the ZMP moves to where the CoM comes to rest in four_foot_s, then stays "
             "there this long");
    v->Visit("zmp_margin_m", &zmp_margin_m, "m", bounds::Closed(0.0, 1.0),
             "distance the ZMP reference keeps from the support triangle's edges");
    v->Visit("load_s", &load_s, "s", duration,
             "a leg that touched down takes its share of the load over this time (the static crawl's too); the ZMP "
             "stays in the last support triangle meanwhile");
    v->Visit("unload_s", &unload_s, "s", duration,
             "a leg gives up its load over this time before it lifts off (the static crawl's too); the ZMP is in the "
             "next support triangle by then");
  }
};

/// The dynamic walk's clock and its ZMP preview. The keys of its gait phases and
/// of its preview sit in the same map as its swing's.
struct DynamicWalkConfig {
  GaitPhases gait = [] {
    GaitPhases g;
    g.start_s = 0.6;
    g.four_foot_s = 0.15;
    g.zmp_speed_mps = 1.0;
    g.base_rise_mps = 0.3;
    g.base_turn_radps = 1.0;
    g.final_s = 0.6;
    g.zmp_margin_m = 0.05;
    return g;
  }();
  double swing_speed_mps = 2.0;
  double min_swing_s = 0.3;
  ZmpPreviewSettings preview = [] {
    ZmpPreviewSettings p;
    p.time_step_s = 0.005;
    p.preview_s = 1.6;
    p.q_error = 1.0;
    p.r_jerk = 1e-6;
    return p;
  }();

  template <class Visitor>
  void Serialize(Visitor* v) {
    gait.Serialize(v);
    v->Visit("swing_speed_mps", &swing_speed_mps, "m/s", bounds::Positive(),
             "peak foot speed of a swing along the plan's swing path");
    v->Visit("min_swing_s", &min_swing_s, "s", bounds::Positive().AtMost(60.0), "shortest swing");
    preview.Serialize(v);
  }
};

}  // namespace rbcp
