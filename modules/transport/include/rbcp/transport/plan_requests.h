#pragma once
/// Plan requests are told apart by their id and their content, never by the order of their ids:
/// an operator picks a random 64-bit id per run, and another client (the simulator's goal
/// events, a second operator) may pick any other.

#include <cstddef>
#include <deque>

#include "rbcp_msgs/plan_request_t.hpp"

namespace rbcp::transport {

/// The same question: id, start (when given), goal and seed (the utime and the budget may differ).
bool SameRequest(const rbcp_msgs::plan_request_t& a, const rbcp_msgs::plan_request_t& b);

/// The requests a process has taken, newest last, so that a late repeat of one superseded since
/// (an operator repeats its request every second) is not taken for a new goal.
class RequestHistory {
 public:
  explicit RequestHistory(std::size_t capacity = 64) : capacity_(capacity) {}

  /// The request taken last, or nullptr.
  const rbcp_msgs::plan_request_t* Latest() const { return taken_.empty() ? nullptr : &taken_.back(); }
  /// True if `request` is the same as one taken before the latest (a stale repeat).
  bool Superseded(const rbcp_msgs::plan_request_t& request) const;
  /// Records `request` as the latest.
  void Take(const rbcp_msgs::plan_request_t& request);

 private:
  std::size_t capacity_;
  std::deque<rbcp_msgs::plan_request_t> taken_;
};

}  // namespace rbcp::transport
