#include "rbcp/transport/status_reporter.h"

#include <unistd.h>

#include <cstdio>

namespace rbcp::transport {

StatusReporter::StatusReporter(lcm::LCM& lcm, std::string process, std::string channel)
    : lcm_(lcm), channel_(std::move(channel)) {
  last_.process = std::move(process);
  last_.pid = static_cast<int32_t>(::getpid());
  last_.state = rbcp_msgs::process_status_t::ALIVE;
}

const char* StatusName(int8_t state) {
  switch (state) {
    case rbcp_msgs::process_status_t::ALIVE: return "alive";
    case rbcp_msgs::process_status_t::BUSY: return "busy";
    case rbcp_msgs::process_status_t::OK: return "ok";
    case rbcp_msgs::process_status_t::FAILED: return "failed";
    default: return "unknown";
  }
}

void StatusReporter::Heartbeat(int64_t utime) {
  Publish(last_.state, utime, last_.input_utime, last_.compute_ms, last_.reason, false);
}

void StatusReporter::Busy(int64_t utime, int64_t input_utime) {
  Publish(rbcp_msgs::process_status_t::BUSY, utime, input_utime, 0.0, "", false);
}

void StatusReporter::Ok(int64_t utime, int64_t input_utime, double compute_ms, const std::string& summary) {
  ++last_.handled;
  Publish(rbcp_msgs::process_status_t::OK, utime, input_utime, compute_ms, summary, true);
}

void StatusReporter::Failed(int64_t utime, int64_t input_utime, double compute_ms, const std::string& reason) {
  ++last_.handled;
  Publish(rbcp_msgs::process_status_t::FAILED, utime, input_utime, compute_ms, reason, true);
}

void StatusReporter::Publish(int8_t state, int64_t utime, int64_t input_utime, double compute_ms,
                             const std::string& reason, bool log) {
  last_.utime = utime;
  last_.state = state;
  last_.reason = reason;
  last_.input_utime = input_utime;
  last_.compute_ms = compute_ms;
  lcm_.publish(channel_, &last_);
  if (verbose_ && log) {
    if (state == rbcp_msgs::process_status_t::FAILED) {
      std::fprintf(stderr, "[%s] failed on input utime %lld: %s\n", last_.process.c_str(),
                   static_cast<long long>(input_utime), reason.c_str());
    } else if (state == rbcp_msgs::process_status_t::OK) {
      std::fprintf(stderr, "[%s] ok: input utime %lld handled in %.3f ms%s%s\n", last_.process.c_str(),
                   static_cast<long long>(input_utime), compute_ms, reason.empty() ? "" : ": ", reason.c_str());
    }
  }
}

}  // namespace rbcp::transport
