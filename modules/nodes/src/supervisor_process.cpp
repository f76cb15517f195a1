#include "rbcp/nodes/supervisor_process.h"

#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <utility>

#include "rbcp/core/error.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/run_loop.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp/transport/wire_check.h"
#include "rbcp_msgs/process_status_t.hpp"

namespace rbcp::nodes {
namespace {

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void SleepS(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

/// Collects every STATUS message (not only the newest: several processes share the channel).
/// Undecodable messages are counted and otherwise ignored.
class StatusListener {
 public:
  StatusListener(lcm::LCM& lcm, Supervisor& supervisor, std::string name)
      : supervisor_(supervisor), name_(std::move(name)) {
    subscription_ = lcm.subscribe(channels::kStatus, &StatusListener::Handle, this);
  }
  long Malformed() const { return malformed_; }

 private:
  void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/) {
    rbcp_msgs::process_status_t msg;
    if (transport::DecodeMessage(rbuf->data, rbuf->data_size, msg)) {
      ++malformed_;
      return;
    }
    if (msg.process == name_ && msg.pid == static_cast<int32_t>(::getpid())) {
      supervisor_.OnOwnStatus(Now());
    } else {
      supervisor_.OnStatus(msg.process, msg.pid, Now());
    }
  }
  Supervisor& supervisor_;
  std::string name_;
  lcm::Subscription* subscription_ = nullptr;
  long malformed_ = 0;
};

}  // namespace

std::string SupervisorName(const std::string& host) {
  if (host.empty()) return kSupervisorName;
  for (const char c : host) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') {
      throw InputError("supervisor: expected a host name of letters, digits, _ and -, got '" + host + "'");
    }
  }
  return std::string(kSupervisorName) + "@" + host;
}

bool IsSupervisorName(const std::string& process) {
  const std::string prefix = std::string(kSupervisorName) + "@";
  return process == kSupervisorName || (process.size() > prefix.size() && process.rfind(prefix, 0) == 0);
}

int RunSupervisor(const SupervisorSpec& spec, lcm::LCM& lcm, const std::string& name, bool verbose,
                  double max_runtime_s) {
  const char* tag = name.c_str();
  // With verbose, every start is printed too; deaths, restarts and stops always are.
  transport::InstallStopHandlers();
  PosixProcessControl control;
  Supervisor supervisor(spec, control);
  StatusListener listener(lcm, supervisor, name);
  transport::StatusReporter status(lcm, name, channels::kStatus);
  status.set_verbose(false);  // the events are printed below, in the supervisor's words
  status.StartBackgroundHeartbeat(0.4);
  const double start = Now();
  std::size_t given_up = 0;
  std::string names;
  for (const ProcessSpec& p : spec.processes) names += (names.empty() ? "" : ", ") + p.name;
  std::fprintf(stderr, "[%s] keeping %s running\n", tag, names.c_str());
  while (!transport::StopRequested()) {
    if (max_runtime_s > 0.0 && Now() - start > max_runtime_s) break;
    for (const std::string& event : supervisor.Step(Now())) {
      const bool first_start = event.find(" started (pid ") != std::string::npos;
      if (verbose || !first_start) std::fprintf(stderr, "[%s] %s\n", tag, event.c_str());
      if (!first_start) status.Ok(0, 0, 0.0, event);  // a death or a restart
    }
    const std::vector<std::string> gone = supervisor.GivenUp();
    if (gone.size() > given_up) {
      given_up = gone.size();
      std::string list;
      for (const std::string& g : gone) list += (list.empty() ? "" : ", ") + g;
      status.Failed(0, 0, 0.0, "given up on " + list + " after " + std::to_string(spec.config.max_restarts) + " restarts");
    }
    if (lcm.handleTimeout(50) < 0 && !transport::StopRequested()) {
      std::fprintf(stderr, "[%s] LCM failed; stopping every process\n", tag);
      break;
    }
  }
  const std::string memory = supervisor.PeakMemory();
  if (!memory.empty()) std::fprintf(stderr, "[%s] peak resident memory: %s\n", tag, memory.c_str());
  for (const std::string& line : supervisor.StopAll(&Now, &SleepS)) {
    std::fprintf(stderr, "[%s] %s\n", tag, line.c_str());
  }
  std::string restarts;
  for (const ProcessSpec& p : spec.processes) {
    const int n = supervisor.Restarts(p.name);
    if (n > 0) restarts += (restarts.empty() ? "" : ", ") + p.name + " " + std::to_string(n);
  }
  std::fprintf(stderr, "[%s] stopped every process; restarts: %s\n", tag,
               restarts.empty() ? "none" : restarts.c_str());
  if (listener.Malformed() > 0) {
    std::fprintf(stderr, "[%s] ignored %ld malformed STATUS messages\n", tag, listener.Malformed());
  }
  return supervisor.GivenUp().empty() ? 0 : 1;
}

}  // namespace rbcp::nodes
