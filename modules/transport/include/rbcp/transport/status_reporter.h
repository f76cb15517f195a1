#pragma once
/// Publishes rbcp_msgs::process_status_t for one process on STATUS, and prints every handled
/// input (ok, or failed with the reason) to stderr so logs say which process failed and why.

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <limits>
#include <mutex>
#include <string>
#include <thread>

#include "rbcp_msgs/process_status_t.hpp"

namespace rbcp::transport {

class StatusReporter {
 public:
  StatusReporter(lcm::LCM& lcm, std::string process, std::string channel);
  ~StatusReporter();
  StatusReporter(const StatusReporter&) = delete;
  StatusReporter& operator=(const StatusReporter&) = delete;

  /// Republishes the current state from a background thread whenever nothing was published for
  /// `period_s` [s, wall clock], also while the process is busy planning, so a supervisor can
  /// tell a long computation from a hung process. A process BUSY with one input for longer than
  /// `max_busy_s` [s, wall clock] (beyond what any input may take with its budget) is stuck: the
  /// heartbeat says so once on stderr and falls silent, and the supervisor restarts the process.
  /// Stops with the reporter.
  void StartBackgroundHeartbeat(double period_s, double max_busy_s = std::numeric_limits<double>::infinity());

  /// `utime` is the simulated time of the latest input (message clock, never the wall clock).
  /// Heartbeat republishes the current state (ALIVE until the first input is handled).
  void Heartbeat(int64_t utime);
  void Busy(int64_t utime, int64_t input_utime);
  /// ALIVE with a one-line note of what the input `input_utime` waits for (the process is idle).
  void Waiting(int64_t utime, int64_t input_utime, const std::string& what);
  /// `summary`: an optional one-line description of the result, published in `reason`.
  void Ok(int64_t utime, int64_t input_utime, double compute_ms, const std::string& summary = "");
  void Failed(int64_t utime, int64_t input_utime, double compute_ms, const std::string& reason);

  rbcp_msgs::process_status_t last() const;
  const std::string& process() const { return process_; }
  /// When false, nothing is printed to stderr (tests, --quiet).
  void set_verbose(bool verbose) { verbose_ = verbose; }
  bool verbose() const { return verbose_; }

 private:
  void Publish(int8_t state, int64_t utime, int64_t input_utime, double compute_ms, const std::string& reason, bool log);
  lcm::LCM& lcm_;
  std::string channel_;
  std::string process_;
  mutable std::mutex mutex_;  // guards last_ and last_publish_ (the heartbeat thread reads them)
  rbcp_msgs::process_status_t last_{};
  std::chrono::steady_clock::time_point last_publish_;
  std::chrono::steady_clock::time_point busy_since_;  ///< when the current BUSY began
  bool verbose_ = true;
  std::thread heartbeat_;
  std::condition_variable stop_cv_;
  bool stop_ = false;
};

/// Human name of a process_status_t state constant.
const char* StatusName(int8_t state);

}  // namespace rbcp::transport
