#include "rbcp/transport/run_loop.h"

#include <chrono>
#include <cstdio>
#include <csignal>
#include <stdexcept>

#include "rbcp/transport/message_faults.h"

namespace rbcp::transport {
namespace {
volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }
}  // namespace

bool StopRequested() { return g_stop != 0; }

void InstallStopHandlers() {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
}

std::unique_ptr<lcm::LCM> OpenLcm(const std::string& url) {
  // Malformed fault rates stop the process here, before it hears anything.
  if (const auto& faults = ProcessMessageFaults()) {
    std::fprintf(stderr, "%s: received messages dropped %.3g, duplicated %.3g, reordered %.3g (seed %llu)\n",
                 kMessageFaultsEnv, faults->drop, faults->duplicate, faults->reorder,
                 static_cast<unsigned long long>(faults->seed));
  }
  auto lcm = std::make_unique<lcm::LCM>(url);
  if (!lcm->good()) {
    const std::string shown = url.empty() ? "the default URL (LCM_DEFAULT_URL or udpm://239.255.76.67:7667)" : url;
    throw std::runtime_error("cannot open LCM at " + shown +
                             "; for udpm:// the host needs a multicast route (tools/netns-run provides one)");
  }
  return lcm;
}

int RunLoop(lcm::LCM& lcm, const std::function<void()>& step, const std::function<void()>& heartbeat,
            const LoopOptions& options) {
  InstallStopHandlers();
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto next_heartbeat = start;
  while (!StopRequested()) {
    const auto now = Clock::now();
    if (heartbeat && now >= next_heartbeat) {
      heartbeat();
      next_heartbeat = now + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(options.heartbeat_period_s));
    }
    if (options.max_runtime_s > 0.0 && std::chrono::duration<double>(now - start).count() > options.max_runtime_s) break;
    if (lcm.handleTimeout(options.handle_timeout_ms) < 0) {
      if (StopRequested()) break;  // the signal interrupted the wait
      return 1;
    }
    // Drain whatever else is queued so step() sees the newest inputs.
    while (lcm.handleTimeout(0) > 0) {
    }
    if (step) step();
  }
  return 0;
}

}  // namespace rbcp::transport
