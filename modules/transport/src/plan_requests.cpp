#include "rbcp/transport/plan_requests.h"

#include <algorithm>

namespace rbcp::transport {

bool SameRequest(const rbcp_msgs::plan_request_t& a, const rbcp_msgs::plan_request_t& b) {
  const auto same3 = [](const double x[3], const double y[3]) { return x[0] == y[0] && x[1] == y[1] && x[2] == y[2]; };
  return a.request_id == b.request_id && a.use_start == b.use_start && a.seed == b.seed &&
         same3(a.goal_position, b.goal_position) && a.goal_yaw == b.goal_yaw &&
         (!a.use_start || (same3(a.start_position, b.start_position) && a.start_yaw == b.start_yaw));
}

bool RequestHistory::Superseded(const rbcp_msgs::plan_request_t& request) const {
  if (taken_.empty()) return false;
  return std::any_of(taken_.begin(), taken_.end() - 1,
                     [&](const rbcp_msgs::plan_request_t& r) { return SameRequest(r, request); });
}

void RequestHistory::Take(const rbcp_msgs::plan_request_t& request) {
  // A request taken again (it was superseded, then asked for anew) moves to the end.
  taken_.erase(std::remove_if(taken_.begin(), taken_.end(),
                              [&](const rbcp_msgs::plan_request_t& r) { return SameRequest(r, request); }),
               taken_.end());
  taken_.push_back(request);
  while (taken_.size() > capacity_) taken_.pop_front();
}

}  // namespace rbcp::transport
