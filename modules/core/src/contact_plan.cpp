#include "rbcp/core/contact_plan.h"

#include "rbcp/core/format.h"

namespace rbcp {

std::optional<std::string> TimingProblem(const ContactPlan& plan) {
  constexpr double kDayS = 86400.0;
  if (plan.states.empty()) return std::nullopt;
  const WholeBodyState& first = plan.states.front();
  if (!std::isnan(first.lift_off_s) || !std::isnan(first.touch_down_s)) {
    return std::string("the first state is timed (it is where the plan starts)");
  }
  std::size_t timed = 0;
  double previous_touch_down_s = 0.0;
  for (std::size_t i = 1; i < plan.states.size(); ++i) {
    const WholeBodyState& s = plan.states[i];
    const std::string where = "state " + std::to_string(i) + ": ";
    if (std::isnan(s.lift_off_s) && std::isnan(s.touch_down_s)) continue;
    ++timed;
    if (!s.HasTiming()) return where + "expected a finite lift-off and touch-down, or neither";
    if (s.lift_off_s < previous_touch_down_s || s.touch_down_s <= s.lift_off_s || s.touch_down_s > kDayS) {
      return where + "expected lift-off at or after " + FixedNumber(previous_touch_down_s, 3) +
             " s and before touch-down (within a day), got " + FixedNumber(s.lift_off_s, 3) + " s and " +
             FixedNumber(s.touch_down_s, 3) + " s";
    }
    previous_touch_down_s = s.touch_down_s;
  }
  if (timed != 0 && timed + 1 != plan.states.size()) return std::string("some steps are timed and others not");
  return std::nullopt;
}

}  // namespace rbcp
