#pragma once
/// Publishes rbcp_msgs::process_status_t for one process on STATUS, and prints every handled
/// input (ok, or failed with the reason) to stderr so logs say which process failed and why.

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <string>

#include "rbcp_msgs/process_status_t.hpp"

namespace rbcp::transport {

class StatusReporter {
 public:
  StatusReporter(lcm::LCM& lcm, std::string process, std::string channel);

  /// `utime` is the simulated time of the latest input (message clock, never the wall clock).
  /// Heartbeat republishes the current state (ALIVE until the first input is handled).
  void Heartbeat(int64_t utime);
  void Busy(int64_t utime, int64_t input_utime);
  /// `summary`: an optional one-line description of the result, published in `reason`.
  void Ok(int64_t utime, int64_t input_utime, double compute_ms, const std::string& summary = "");
  void Failed(int64_t utime, int64_t input_utime, double compute_ms, const std::string& reason);

  const rbcp_msgs::process_status_t& last() const { return last_; }
  const std::string& process() const { return last_.process; }
  /// When false, nothing is printed to stderr (tests, --quiet).
  void set_verbose(bool verbose) { verbose_ = verbose; }

 private:
  void Publish(int8_t state, int64_t utime, int64_t input_utime, double compute_ms, const std::string& reason, bool log);
  lcm::LCM& lcm_;
  std::string channel_;
  rbcp_msgs::process_status_t last_{};
  bool verbose_ = true;
};

/// Human name of a process_status_t state constant.
const char* StatusName(int8_t state);

}  // namespace rbcp::transport
