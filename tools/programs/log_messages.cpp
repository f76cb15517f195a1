#include "log_messages.h"

#include <lcm/lcm-cpp.hpp>

#include "rbcp/core/error.h"
#include "rbcp/transport/message_parts.h"

namespace rbcp::logs {

long ReadLogMessages(const std::string& path, const OnLogMessage& on_message, const OnLogProblem& on_problem) {
  lcm::LogFile log(path, "r");
  if (!log.good()) throw InputError("cannot read the LCM log " + path);
  transport::PartJoiner joiner;
  long events = 0;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    ++events;
    const int64_t timestamp = e->timestamp;
    const std::string problem = joiner.Add(
        e->channel, e->data, static_cast<std::size_t>(e->datalen),
        [&](const std::string& channel, const void* data, std::size_t size) { on_message(timestamp, channel, data, size); });
    if (!problem.empty()) on_problem(problem);
  }
  return events;
}

}  // namespace rbcp::logs
