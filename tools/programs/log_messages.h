#pragma once
/// The messages of a recorded run's LCM log (tools/launch's run.lcmlog), whole: shared by run_log
/// and replay_log, which read a log to the end before they use it.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace rbcp::logs {

/// A whole message of a log at its receive time [us]; `data` is valid during the call only.
using OnLogMessage =
    std::function<void(int64_t timestamp_us, const std::string& channel, const void* data, std::size_t size)>;
/// Why a part of a message was dropped (naming its channel).
using OnLogProblem = std::function<void(const std::string& problem)>;

/// Calls on_message for every message of the LCM log at `path`, in the log's order: a message sent
/// in parts (TERRAIN/PART) once, when its last part is read, at that part's receive time; calls
/// on_problem for a part that cannot be joined. Returns how many events the log holds. Throws
/// InputError when the log cannot be read.
long ReadLogMessages(const std::string& path, const OnLogMessage& on_message, const OnLogProblem& on_problem);

}  // namespace rbcp::logs
