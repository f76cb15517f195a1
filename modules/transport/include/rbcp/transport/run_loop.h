#pragma once
/// Process plumbing shared by every node's main(): opening LCM with a clear error, and the
/// handle/step loop that runs until SIGINT or SIGTERM.

#include <lcm/lcm-cpp.hpp>

#include <functional>
#include <memory>
#include <string>

namespace rbcp::transport {

/// Opens LCM at `url` ("" = LCM_DEFAULT_URL or LCM's default). Throws std::runtime_error with
/// the URL and the usual cause when LCM cannot start (for udpm: no multicast route).
std::unique_ptr<lcm::LCM> OpenLcm(const std::string& url);

struct LoopOptions {
  double heartbeat_period_s = 1.0;  ///< how often `heartbeat` runs [s, wall clock]
  int handle_timeout_ms = 20;       ///< longest wait for traffic before `step` runs again
  double max_runtime_s = 0.0;       ///< stop after this long [s, wall clock]; 0 = until signalled
};

/// Alternates lcm.handleTimeout() and step() until SIGINT/SIGTERM (or max_runtime_s), calling
/// heartbeat() periodically. Returns 0 on a clean stop, 1 if LCM reported an error.
int RunLoop(lcm::LCM& lcm, const std::function<void()>& step, const std::function<void()>& heartbeat,
            const LoopOptions& options = {});

/// True once SIGINT or SIGTERM arrived (after InstallStopHandlers()).
bool StopRequested();
void InstallStopHandlers();

}  // namespace rbcp::transport
