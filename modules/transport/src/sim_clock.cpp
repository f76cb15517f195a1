#include "rbcp/transport/sim_clock.h"

#include <algorithm>

#include "rbcp/core/format.h"

namespace rbcp::transport {
namespace {

std::string Seconds(int64_t utime) { return FixedNumber(static_cast<double>(utime) * 1e-6, 3) + " s"; }

std::string Insane(int64_t utime, const std::string& what) {
  if (utime >= 0 && utime <= SimClock::kMaxUtime) return "";
  return what + ": utime " + std::to_string(utime) + " us is not a simulated time (expected 0 to " +
         std::to_string(SimClock::kMaxUtime) + ")";
}

}  // namespace

std::string SimClock::World(int64_t utime, const std::string& what) {
  if (last_world_offered_ == utime) return "";
  last_world_offered_ = utime;
  if (std::string bad = Insane(utime, what); !bad.empty()) return bad;
  now_ = utime;
  world_heard_ = true;
  return "";
}

std::string SimClock::Input(int64_t utime, const std::string& what) {
  if (std::string bad = Insane(utime, what); !bad.empty()) return bad;
  if (world_heard_ && utime - now_ > kMaxAhead_us) {
    return what + ": utime " + Seconds(utime) + " lies " + Seconds(utime - now_) + " ahead of the simulated time " +
           Seconds(now_) + " (at most " + Seconds(kMaxAhead_us) + ")";
  }
  now_ = std::max(now_, utime);
  return "";
}

}  // namespace rbcp::transport
