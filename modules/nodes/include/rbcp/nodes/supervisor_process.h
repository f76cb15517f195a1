#pragma once
/// The supervisor as a process: the Supervisor's decisions driven by the STATUS channel and a
/// monotonic clock, its events logged on stderr and published on STATUS (process "supervisor",
/// or "supervisor@HOST" when each host of a split pipeline runs its own).

#include <lcm/lcm-cpp.hpp>

#include <string>

#include "rbcp/nodes/supervisor.h"

namespace rbcp::nodes {

inline constexpr const char* kSupervisorName = "supervisor";

/// The STATUS process name of the supervisor on `host`: "supervisor@HOST", or "supervisor" when
/// `host` is empty (a single host). Throws InputError unless `host` is letters, digits, _ and -.
std::string SupervisorName(const std::string& host);
/// True for a name SupervisorName gives: the STATUS of a supervisor, on any host.
bool IsSupervisorName(const std::string& process);

/// Runs the spec's processes until SIGINT or SIGTERM (or max_runtime_s > 0 of wall time), then
/// stops them all. `name` (SupervisorName) is its process name on STATUS and in front of its log
/// lines. Every restart is published on STATUS as OK with the event, a process given up on as
/// FAILED. Returns 0, or 1 when a process was given up on.
int RunSupervisor(const SupervisorSpec& spec, lcm::LCM& lcm, const std::string& name, bool verbose,
                  double max_runtime_s);

}  // namespace rbcp::nodes
