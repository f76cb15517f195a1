#pragma once
/// The simulated time a process has heard of. Message utimes are a process's only clock (it never
/// reads the wall clock for it), so one message with a wrong time must not stop it: the world's
/// messages (ROBOT_STATE, TERRAIN) set the clock, also back in time (a restarted world counts from
/// 0 again); any other input (a request, a path, surfaces) may move it forward by at most
/// kMaxAhead_us, and a time outside [0, kMaxUtime] is no time at all.

#include <cstdint>
#include <optional>
#include <string>

namespace rbcp::transport {

class SimClock {
 public:
  static constexpr int64_t kMaxUtime = int64_t{10'000'000} * 1'000'000;  ///< [us] about 116 days
  static constexpr int64_t kMaxAhead_us = int64_t{600} * 1'000'000;      ///< [us] 10 minutes

  /// A world message at `utime`: the clock follows it. Returns "" or why the time is rejected
  /// (the clock then keeps its time); `what` names the message. The time of the last world
  /// message offered, offered again (a node looks at its latest ROBOT_STATE every step), changes
  /// nothing and is not rejected again.
  std::string World(int64_t utime, const std::string& what);
  /// Another input at `utime`: moves the clock forward to it. Returns "" or why it is rejected:
  /// outside [0, kMaxUtime], or more than kMaxAhead_us ahead of a world already heard.
  std::string Input(int64_t utime, const std::string& what);
  /// The latest time heard [us], 0 before any.
  int64_t Now() const { return now_; }

 private:
  int64_t now_ = 0;
  bool world_heard_ = false;
  std::optional<int64_t> last_world_offered_;
};

}  // namespace rbcp::transport
