#pragma once
/// The supervisor as a process: the Supervisor's decisions driven by the STATUS channel and a
/// monotonic clock, its events logged on stderr and published on STATUS (process "supervisor").

#include <lcm/lcm-cpp.hpp>

#include "rbcp/nodes/supervisor.h"

namespace rbcp::nodes {

inline constexpr const char* kSupervisorName = "supervisor";

/// Runs the spec's processes until SIGINT or SIGTERM (or max_runtime_s > 0 of wall time), then
/// stops them all. Every restart is published on STATUS as OK with the event, a process given up
/// on as FAILED. Returns 0, or 1 when a process was given up on.
int RunSupervisor(const SupervisorSpec& spec, lcm::LCM& lcm, bool verbose, double max_runtime_s);

}  // namespace rbcp::nodes
