#pragma once
/// A node of the step search.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "rbcp/core/contact_plan.h"
#include "rbcp/core/leg.h"

namespace rbcp::contact_planner_detail {

/// How the search walks: the crawl timing and how much of a swing's body shift is kept after it.
struct CrawlProfile {
  double gait_advance_s = 0.0;  ///< [s] path time between crawl steps (0: step only when a foot must)
  double keep_fraction = 1.0;   ///< [-] fraction of the swing shift kept after touch-down
};

/// One node of the step search: a state, the path time it stands at and the body shift.
struct Node {
  WholeBodyState state;
  double t = 0.0;
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();  ///< base offset from the path, path heading frame
  int steps_at_time = 0;                            ///< steps taken since the trunk last advanced
  std::array<bool, kNumLegs> stepped_at_time{};     ///< legs that stepped since then
  // Search bookkeeping.
  bool expanded = false;
  bool goal = false;           ///< the node completes the plan
  struct Option {
    Leg leg;
    double t;
    int lead_factor_index;     ///< the target's lead: index into foothold.lead_time_factors
    bool goal_step;            ///< toward the reference foot at the path end
    int shift_start = 0;       ///< where the shift search starts: index of ShiftStart()
  };
  std::vector<Option> options;
  std::size_t next_option = 0;
  std::set<std::tuple<int, long, int>> exhausted;  ///< (leg, time key, shift start) with no valid candidate
  std::set<std::pair<int, long>> repositions;      ///< (leg, time key) added as blocking a lift-off
  struct Child {
    Leg leg;
    double t;
    Eigen::Vector3d foot;
  };
  std::vector<Child> children;  ///< steps already explored from this node
};

}  // namespace rbcp::contact_planner_detail
