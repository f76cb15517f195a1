#include "rbcp/transport/sim_clock.h"

#include <algorithm>

#include "rbcp/core/format.h"

namespace rbcp::transport {
namespace {

std::string Seconds(int64_t utime) { return FixedNumber(static_cast<double>(utime) * 1e-6, 3) + " s"; }

std::optional<RejectedTime> NotASimTime(int64_t utime, const std::string& what) {
  if (utime >= 0 && utime <= SimClock::kMaxUtime) return std::nullopt;
  return RejectedTime{RejectedTime::Kind::kNotASimTime, what, utime, 0};
}

}  // namespace

std::string RejectedTime::Describe() const {
  switch (kind) {
    case Kind::kNotASimTime:
      return what + ": utime " + std::to_string(utime) + " us is not a simulated time (expected 0 to " +
             std::to_string(SimClock::kMaxUtime) + ")";
    case Kind::kTooFarAhead:
      return what + ": utime " + Seconds(utime) + " lies " + Seconds(utime - now) + " ahead of the simulated time " +
             Seconds(now) + " (at most " + Seconds(SimClock::kMaxAhead_us) + ")";
  }
  return what + ": utime " + std::to_string(utime) + " us rejected";
}

std::optional<RejectedTime> SimClock::World(int64_t utime, const std::string& what) {
  if (last_world_offered_ == utime) return std::nullopt;
  last_world_offered_ = utime;
  if (std::optional<RejectedTime> bad = NotASimTime(utime, what)) return bad;
  now_ = utime;
  world_heard_ = true;
  return std::nullopt;
}

std::optional<RejectedTime> SimClock::Input(int64_t utime, const std::string& what) {
  if (std::optional<RejectedTime> bad = NotASimTime(utime, what)) return bad;
  if (world_heard_ && utime - now_ > kMaxAhead_us) {
    return RejectedTime{RejectedTime::Kind::kTooFarAhead, what, utime, now_};
  }
  now_ = std::max(now_, utime);
  return std::nullopt;
}

}  // namespace rbcp::transport
