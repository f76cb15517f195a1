#include "rbcp/transport/status_reporter.h"

#include <unistd.h>

#include <cstdio>

namespace rbcp::transport {

StatusReporter::StatusReporter(lcm::LCM& lcm, std::string process, std::string channel)
    : lcm_(lcm), channel_(std::move(channel)), process_(std::move(process)) {
  last_.process = process_;
  last_.pid = static_cast<int32_t>(::getpid());
  last_.state = rbcp_msgs::process_status_t::ALIVE;
}

StatusReporter::~StatusReporter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  stop_cv_.notify_all();
  if (heartbeat_.joinable()) heartbeat_.join();
}

void StatusReporter::StartBackgroundHeartbeat(double period_s, double max_busy_s) {
  if (heartbeat_.joinable() || !(period_s > 0.0)) return;
  using Duration = std::chrono::steady_clock::duration;
  const auto period = std::chrono::duration_cast<Duration>(std::chrono::duration<double>(period_s));
  // An infinite bound never ends a BUSY (and does not overflow the clock's duration).
  const bool bounded = max_busy_s < 1e9;
  const auto max_busy = bounded ? std::chrono::duration_cast<Duration>(std::chrono::duration<double>(max_busy_s)) : Duration{};
  heartbeat_ = std::thread([this, period, bounded, max_busy, max_busy_s] {
    std::unique_lock<std::mutex> lock(mutex_);
    bool stuck_reported = false;
    while (!stop_) {
      const auto now = std::chrono::steady_clock::now();
      const bool stuck = bounded && last_.state == rbcp_msgs::process_status_t::BUSY && now - busy_since_ > max_busy;
      if (stuck) {
        if (!stuck_reported) {
          std::fprintf(stderr, "[%s] busy with input utime %lld for more than %.1f s, beyond what any input may take: "
                               "STATUS stops, for the supervisor to restart this process\n",
                       process_.c_str(), static_cast<long long>(last_.input_utime), max_busy_s);
          stuck_reported = true;
        }
        stop_cv_.wait_for(lock, period);
        continue;
      }
      stuck_reported = false;
      const auto due = last_publish_ + period;
      if (now >= due) {
        last_publish_ = now;
        lcm_.publish(channel_, &last_);  // LCM's functions are thread-safe
        continue;
      }
      stop_cv_.wait_until(lock, due);
    }
  });
}

rbcp_msgs::process_status_t StatusReporter::last() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_;
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
  const rbcp_msgs::process_status_t now = last();
  Publish(now.state, utime, now.input_utime, now.compute_ms, now.reason, false);
}

void StatusReporter::Busy(int64_t utime, int64_t input_utime) {
  Publish(rbcp_msgs::process_status_t::BUSY, utime, input_utime, 0.0, "", false);
}

void StatusReporter::Waiting(int64_t utime, int64_t input_utime, const std::string& what) {
  Publish(rbcp_msgs::process_status_t::ALIVE, utime, input_utime, 0.0, what, false);
}

void StatusReporter::Ok(int64_t utime, int64_t input_utime, double compute_ms, const std::string& summary) {
  Publish(rbcp_msgs::process_status_t::OK, utime, input_utime, compute_ms, summary, true);
}

void StatusReporter::Failed(int64_t utime, int64_t input_utime, double compute_ms, const std::string& reason) {
  Publish(rbcp_msgs::process_status_t::FAILED, utime, input_utime, compute_ms, reason, true);
}

void StatusReporter::Publish(int8_t state, int64_t utime, int64_t input_utime, double compute_ms,
                             const std::string& reason, bool log) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (log) ++last_.handled;  // OK and FAILED answer an input
    if (state == rbcp_msgs::process_status_t::BUSY && last_.state != rbcp_msgs::process_status_t::BUSY) {
      busy_since_ = std::chrono::steady_clock::now();
    }
    last_.utime = utime;
    last_.state = state;
    last_.reason = reason;
    last_.input_utime = input_utime;
    last_.compute_ms = compute_ms;
    last_publish_ = std::chrono::steady_clock::now();
    lcm_.publish(channel_, &last_);
  }
  if (verbose_ && log) {
    if (state == rbcp_msgs::process_status_t::FAILED) {
      std::fprintf(stderr, "[%s] failed on input utime %lld: %s\n", process_.c_str(),
                   static_cast<long long>(input_utime), reason.c_str());
    } else if (state == rbcp_msgs::process_status_t::OK) {
      std::fprintf(stderr, "[%s] ok: input utime %lld handled in %.3f ms%s%s\n", process_.c_str(),
                   static_cast<long long>(input_utime), compute_ms, reason.empty() ? "" : ": ", reason.c_str());
    }
  }
}

}  // namespace rbcp::transport
