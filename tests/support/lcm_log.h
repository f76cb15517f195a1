#pragma once
// Reading a recorded LCM log into memory, for playback tests.

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "rbcp/transport/wire_check.h"

namespace rbcp::testing {

struct RecordedEvent {
  int64_t timestamp = 0;  // logger receive time [us]
  std::string channel;
  std::vector<uint8_t> data;

  template <typename Msg>
  bool DecodeInto(Msg& msg) const {
    return transport::DecodeMessage(data.data(), data.size(), msg).empty();
  }
};

inline std::vector<RecordedEvent> ReadLog(const std::string& path) {
  std::vector<RecordedEvent> events;
  lcm::LogFile log(path, "r");
  if (!log.good()) return events;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    const auto* bytes = static_cast<const uint8_t*>(e->data);
    events.push_back({e->timestamp, e->channel, std::vector<uint8_t>(bytes, bytes + e->datalen)});
  }
  return events;
}

}  // namespace rbcp::testing
