#pragma once
// Reading a recorded LCM log into memory, for playback tests.

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/wire_check.h"

namespace rbcp::testing {

struct RecordedEvent {
  int64_t timestamp = 0;  // logger receive time [us]
  std::string channel;
  std::vector<uint8_t> data;

  template <typename Msg>
  bool DecodeInto(Msg& msg) const {
    return !transport::DecodeMessage(data.data(), data.size(), msg);
  }
};

/// The log's messages, whole: a message sent in parts (CHANNEL/PART) is one event of CHANNEL at
/// its last part's time.
inline std::vector<RecordedEvent> ReadLog(const std::string& path) {
  std::vector<RecordedEvent> events;
  lcm::LogFile log(path, "r");
  if (!log.good()) return events;
  transport::PartJoiner joiner;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    const int64_t timestamp = e->timestamp;
    joiner.Add(e->channel, e->data, static_cast<std::size_t>(e->datalen),
               [&](const std::string& channel, const void* data, std::size_t size) {
                 const auto* bytes = static_cast<const uint8_t*>(data);
                 events.push_back({timestamp, channel, std::vector<uint8_t>(bytes, bytes + size)});
               });
  }
  return events;
}

}  // namespace rbcp::testing
