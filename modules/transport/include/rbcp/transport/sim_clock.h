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

/// Why a message's utime was not taken as the simulated time.
struct RejectedTime {
  enum class Kind {
    kNotASimTime,  ///< outside [0, SimClock::kMaxUtime]
    kTooFarAhead,  ///< an input more than SimClock::kMaxAhead_us ahead of the world's time `now`
  };
  Kind kind = Kind::kNotASimTime;
  std::string what;  ///< the message, e.g. its channel
  int64_t utime = 0;  ///< [us] the rejected time
  int64_t now = 0;    ///< [us] kTooFarAhead: the clock's time

  /// "<what>: utime -1 us is not a simulated time (expected 0 to ...)", "<what>: utime 603.000 s
  /// lies 601.000 s ahead of the simulated time 2.000 s (at most 600.000 s)".
  std::string Describe() const;
};

class SimClock {
 public:
  static constexpr int64_t kMaxUtime = int64_t{10'000'000} * 1'000'000;  ///< [us] about 116 days
  static constexpr int64_t kMaxAhead_us = int64_t{600} * 1'000'000;      ///< [us] 10 minutes

  /// A world message at `utime`: the clock follows it. Returns why the time is rejected (the
  /// clock then keeps its time), nullopt when taken; `what` names the message. The time of the
  /// last world message offered, offered again (a node looks at its latest ROBOT_STATE every
  /// step), changes nothing and is not rejected again.
  std::optional<RejectedTime> World(int64_t utime, const std::string& what);
  /// Another input at `utime`: moves the clock forward to it. Returns why it is rejected (outside
  /// [0, kMaxUtime], or more than kMaxAhead_us ahead of a world already heard), nullopt when taken.
  std::optional<RejectedTime> Input(int64_t utime, const std::string& what);
  /// The latest time heard [us], 0 before any.
  int64_t Now() const { return now_; }

 private:
  int64_t now_ = 0;
  bool world_heard_ = false;
  std::optional<int64_t> last_world_offered_;
};

}  // namespace rbcp::transport
