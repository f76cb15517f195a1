#pragma once
/// The supervisor keeps the pipeline's processes running, as a robot's process manager would: a
/// process that dies is restarted after a back-off that doubles with every restart in a row; one
/// that stops answering (no STATUS for heartbeat_timeout_s, or none within startup_timeout_s of
/// its start) is named, killed and restarted. Stopping the supervisor stops every process, a
/// hung or stopped one included (SIGCONT and SIGTERM, then SIGKILL after a grace period).
///
/// The decisions are made here from what the caller reports (STATUS received, time); starting,
/// signalling and reaping processes goes through ProcessControl, so they can be tested without
/// real processes.

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/yaml_reader.h"

namespace rbcp::nodes {

struct SupervisionConfig {
  double heartbeat_timeout_s = 2.0;  ///< [s] silence that makes a running process "not answering"
  double startup_timeout_s = 60.0;   ///< [s] longest wait for a started process's first STATUS
  double backoff_initial_s = 0.5;    ///< [s] wait before the first restart
  double backoff_max_s = 8.0;        ///< [s] the back-off doubles up to this
  double healthy_after_s = 30.0;     ///< [s] running this long resets the back-off
  int max_restarts = 10;             ///< restarts per process before giving up (0: never restart)
  double stop_grace_s = 3.0;         ///< [s] from SIGTERM to SIGKILL when stopping
};

/// One supervised process: its name (the `process` field of its STATUS), command line and log.
struct ProcessSpec {
  std::string name;
  std::vector<std::string> command;  ///< program path first
  std::string log;                   ///< stdout and stderr are appended here
};

struct SupervisorSpec {
  SupervisionConfig config;
  std::vector<ProcessSpec> processes;
  /// Reads a spec file (strict YAML: heartbeat_timeout_s, startup_timeout_s, backoff_initial_s,
  /// backoff_max_s, healthy_after_s, max_restarts, stop_grace_s, processes: [{name, command, log}]).
  static SupervisorSpec LoadFile(const std::string& path);
  static SupervisorSpec Load(const YamlMap& map);
};

/// How a process ended, as waitpid reports it.
struct ProcessExit {
  int pid = 0;
  std::string how;  ///< "exited with status 1", "killed by signal 9 (Killed)"
};

/// The operating system's side: start, signal and reap processes.
class ProcessControl {
 public:
  virtual ~ProcessControl() = default;
  /// Starts the process; returns its pid. Throws std::runtime_error when it cannot.
  virtual int Start(const ProcessSpec& spec, const std::string& log_header) = 0;
  virtual void Terminate(int pid) = 0;  ///< SIGCONT then SIGTERM: stop, even when stopped
  virtual void Kill(int pid) = 0;       ///< SIGKILL
  /// One child that has ended since the last call, without waiting; nullopt when none.
  virtual std::optional<ProcessExit> Reap() = 0;
  /// Peak resident memory [bytes] of a running process, 0 when unknown.
  virtual long PeakResidentBytes(int /*pid*/) { return 0; }
  /// Kills and reaps what the started processes left behind outside their process groups (a
  /// grandchild that made itself a session of its own), once they have stopped; returns how many.
  virtual int KillStrays() { return 0; }
};

/// fork/exec with the child in its own process group, killed with the supervisor
/// (PR_SET_PDEATHSIG), stdin from /dev/null, stdout and stderr appended to the spec's log. The
/// caller becomes a child subreaper (PR_SET_CHILD_SUBREAPER): whatever its children leave behind
/// becomes its child when they end, never init's, so KillStrays can find it.
class PosixProcessControl : public ProcessControl {
 public:
  PosixProcessControl();
  int Start(const ProcessSpec& spec, const std::string& log_header) override;
  void Terminate(int pid) override;
  void Kill(int pid) override;
  std::optional<ProcessExit> Reap() override;
  long PeakResidentBytes(int pid) override;
  int KillStrays() override;
};

/// A process as /proc/PID/stat describes it.
struct ProcessEntry {
  int pid = 0;
  int ppid = 0;
  int pgrp = 0;
  char state = '?';  ///< R, S, D, T, Z (zombie: ended, not yet reaped), ...
};
/// Every process of the machine (of this PID namespace).
std::vector<ProcessEntry> ListProcesses();

class Supervisor {
 public:
  /// Nothing is started before the first Step().
  Supervisor(SupervisorSpec spec, ProcessControl& control);

  /// A STATUS message from `process` with pid `pid` arrived at `now` [s, monotonic clock].
  /// STATUS of an earlier instance (another pid) or of an unknown process is ignored.
  void OnStatus(const std::string& process, int pid, double now);

  /// The supervisor's own STATUS came back at `now`: its LCM reception works. Once heard, a
  /// supervisor that stops hearing itself for heartbeat_timeout_s judges no process silent (the
  /// silence is its own: a starved or overflowing receiver), and gives each a fresh
  /// heartbeat_timeout_s when it hears again.
  void OnOwnStatus(double now);

  /// Reaps ended processes, kills silent ones, starts those due. Returns what happened, one
  /// line per event ("contact_planner (pid 123) died: killed by signal 9 (Killed); restart 1 in
  /// 0.5 s").
  std::vector<std::string> Step(double now);

  /// Stops every process: SIGCONT and SIGTERM, reaping until all ended or stop_grace_s passed
  /// (measured with `clock`), then SIGKILL and reap. Returns a line per process that needed
  /// SIGKILL. `clock` returns the monotonic time [s]; `sleep_s` waits (a fake in tests).
  std::vector<std::string> StopAll(double (*clock)(), void (*sleep_s)(double));

  /// Names of processes that were restarted max_restarts times and died again (not restarted).
  std::vector<std::string> GivenUp() const;
  int Restarts(const std::string& name) const;
  /// The running instance's pid, nullopt while it is down.
  std::optional<int> Pid(const std::string& name) const;
  /// "anymal_sim 120.3 MB, contact_planner 54.1 MB": peak resident memory of the running ones.
  std::string PeakMemory() const;

 private:
  struct Child {
    ProcessSpec spec;
    std::optional<int> pid;
    bool ever_started = false;
    double started_at = 0.0;
    std::optional<double> last_status;  ///< time of the latest STATUS of this instance
    double start_due = 0.0;             ///< when down: when to start again
    int restarts = 0;                   ///< restarts so far
    int backoff_level = 0;              ///< restarts in a row without a healthy run
    bool given_up = false;
  };
  void Down(Child& child, double now, const std::string& why, std::vector<std::string>* events);
  /// False while the supervisor's own STATUS has not come back for heartbeat_timeout_s.
  bool Hearing(double now, std::vector<std::string>* events);
  std::optional<double> last_own_status_;
  bool deaf_ = false;
  Child* ByPid(int pid);

  SupervisionConfig config_;
  ProcessControl& control_;
  std::vector<Child> children_;
};

}  // namespace rbcp::nodes
