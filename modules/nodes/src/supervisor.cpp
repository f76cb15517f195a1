#include "rbcp/nodes/supervisor.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "rbcp/core/config_checks.h"
#include "rbcp/core/error.h"
#include "rbcp/core/format.h"

namespace rbcp::nodes {
namespace {

/// `name` with every byte outside printable ASCII written as \xNN, quoted.
std::string EscapedName(const std::string& name) {
  std::string out = "'";
  for (const char ch : name.substr(0, 80)) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte >= 0x20 && byte < 0x7f && ch != '\\') {
      out += ch;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "\\x%02x", byte);
      out += hex;
    }
  }
  return out + (name.size() > 80 ? "...'" : "'");
}

}  // namespace

SupervisorSpec SupervisorSpec::Load(const YamlMap& map) {
  SupervisorSpec spec;
  SupervisionConfig& c = spec.config;
  c.heartbeat_timeout_s = map.Double("heartbeat_timeout_s");
  c.startup_timeout_s = map.Double("startup_timeout_s");
  c.backoff_initial_s = map.Double("backoff_initial_s");
  c.backoff_max_s = map.Double("backoff_max_s");
  c.healthy_after_s = map.Double("healthy_after_s");
  c.max_restarts = map.Int("max_restarts");
  c.stop_grace_s = map.Double("stop_grace_s");
  // Bounds that keep the supervisor responsive: its waits are at most these long, and a restart
  // loop cannot spin (a back-off of at least 10 ms).
  constexpr double kMaxWait_s = 3600.0;
  const ConfigChecks check(map.Where());
  check.InRange("heartbeat_timeout_s", c.heartbeat_timeout_s, 0.05, kMaxWait_s, "s");
  check.InRange("startup_timeout_s", c.startup_timeout_s, 0.05, kMaxWait_s, "s");
  check.InRange("backoff_initial_s", c.backoff_initial_s, 0.01, kMaxWait_s, "s");
  check.InRange("healthy_after_s", c.healthy_after_s, 0.01, kMaxWait_s, "s");
  check.InRange("stop_grace_s", c.stop_grace_s, 0.01, 60.0, "s");
  if (!(c.backoff_max_s >= c.backoff_initial_s)) {
    check.Fail("backoff_max_s", "at least backoff_initial_s (" + ConfigNumber(c.backoff_initial_s) + ")",
               ConfigNumber(c.backoff_max_s));
  }
  check.InRange("backoff_max_s", c.backoff_max_s, c.backoff_initial_s, kMaxWait_s, "s");
  check.InRange("max_restarts", c.max_restarts, 0, 10000);
  for (const YamlMap& p : map.MapList("processes")) {
    ProcessSpec s;
    s.name = p.String("name");
    s.command = p.Strings("command");
    s.log = p.String("log");
    if (s.name.empty()) p.Fail("name", "expected a process name, got an empty string");
    // Names go into logs, STATUS and terminals: letters, digits and _ . - @ only.
    const bool plain = std::all_of(s.name.begin(), s.name.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-' || ch == '@';
    });
    if (!plain || s.name.size() > 64) {
      p.Fail("name", "expected at most 64 letters, digits, '_', '.', '-' or '@', got " + EscapedName(s.name));
    }
    if (s.command.empty() || s.command.front().empty()) p.Fail("command", "expected a program and its arguments");
    if (s.log.empty()) p.Fail("log", "expected a log file path, got an empty string");
    for (const ProcessSpec& other : spec.processes) {
      if (other.name == s.name) p.Fail("name", "process '" + s.name + "' is listed twice");
    }
    p.RejectUnknownKeys();
    spec.processes.push_back(std::move(s));
  }
  if (spec.processes.empty()) map.Fail("processes", "expected at least one process");
  map.RejectUnknownKeys();
  return spec;
}

SupervisorSpec SupervisorSpec::LoadFile(const std::string& path) { return Load(YamlMap::LoadFile(path)); }

// ---------------------------------------------------------------------------------------------

std::vector<ProcessEntry> ListProcesses() {
  std::vector<ProcessEntry> out;
  DIR* proc = ::opendir("/proc");
  if (proc == nullptr) return out;
  while (const dirent* entry = ::readdir(proc)) {
    if (!std::isdigit(static_cast<unsigned char>(entry->d_name[0]))) continue;
    std::ifstream stat(std::string("/proc/") + entry->d_name + "/stat");
    std::string text;
    if (!std::getline(stat, text)) continue;  // ended meanwhile
    // "PID (COMM) STATE PPID PGRP ...": COMM may hold spaces and parentheses, the last ')' ends it.
    const std::size_t close = text.rfind(')');
    if (close == std::string::npos) continue;
    ProcessEntry e;
    e.pid = std::atoi(text.c_str());
    std::istringstream fields(text.substr(close + 1));
    if (fields >> e.state >> e.ppid >> e.pgrp) out.push_back(e);
  }
  ::closedir(proc);
  return out;
}

PosixProcessControl::PosixProcessControl() { ::prctl(PR_SET_CHILD_SUBREAPER, 1); }

int PosixProcessControl::Start(const ProcessSpec& spec, const std::string& log_header) {
  // Non-blocking: a FIFO without a reader would block the supervisor here for ever. Only a
  // regular file is a log.
  struct stat info {};
  if (::stat(spec.log.c_str(), &info) == 0 && !S_ISREG(info.st_mode)) {
    throw std::runtime_error("the log " + spec.log + " is not a regular file");
  }
  const int log = ::open(spec.log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NONBLOCK | O_NOCTTY, 0644);
  if (log < 0) throw std::runtime_error("cannot open the log " + spec.log + ": " + std::strerror(errno));
  if (::fstat(log, &info) != 0 || !S_ISREG(info.st_mode)) {
    ::close(log);
    throw std::runtime_error("the log " + spec.log + " is not a regular file");
  }
  ::fcntl(log, F_SETFL, ::fcntl(log, F_GETFL) & ~O_NONBLOCK);
  if (!log_header.empty()) {
    const std::string line = log_header + "\n";
    if (::write(log, line.data(), line.size()) < 0) {
      // The header is a courtesy; the process starts all the same.
    }
  }
  std::vector<char*> argv;
  for (const std::string& a : spec.command) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(log);
    throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  }
  if (pid == 0) {
    // The child: its own process group (a terminal's Ctrl-C reaches the supervisor, which stops
    // the children in order), killed when the supervisor dies, output to the log.
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the supervisor died before prctl took effect
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    ::signal(SIGCHLD, SIG_DFL);
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, STDIN_FILENO);
    ::dup2(log, STDOUT_FILENO);
    ::dup2(log, STDERR_FILENO);
    ::execv(argv[0], argv.data());
    const std::string err = std::string("supervisor: cannot run ") + spec.command.front() + ": " + std::strerror(errno) + "\n";
    if (::write(STDERR_FILENO, err.data(), err.size()) < 0) {
      // Nothing more can be reported.
    }
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here, so the group exists before the first signal to it
  ::close(log);
  return static_cast<int>(pid);
}

namespace {

/// Signals the process's group (the process and whatever it started), or the process alone
/// when the group is gone.
void SignalGroup(int pid, int sig) {
  if (::kill(-pid, sig) != 0) ::kill(pid, sig);
}

}  // namespace

void PosixProcessControl::Terminate(int pid) {
  SignalGroup(pid, SIGCONT);
  SignalGroup(pid, SIGTERM);
}

void PosixProcessControl::Kill(int pid) { SignalGroup(pid, SIGKILL); }

std::optional<ProcessExit> PosixProcessControl::Reap() {
  int status = 0;
  const pid_t pid = ::waitpid(-1, &status, WNOHANG);
  if (pid <= 0) return std::nullopt;
  ProcessExit e;
  e.pid = static_cast<int>(pid);
  if (WIFEXITED(status)) {
    e.how = "exited with status " + std::to_string(WEXITSTATUS(status));
  } else if (WIFSIGNALED(status)) {
    e.how = "killed by signal " + std::to_string(WTERMSIG(status)) + " (" + ::strsignal(WTERMSIG(status)) + ")";
  } else {
    e.how = "ended (wait status " + std::to_string(status) + ")";
  }
  return e;
}

int PosixProcessControl::KillStrays() {
  // A stray's own children become ours when it ends: a few rounds until none is left.
  const pid_t self = ::getpid();
  std::set<int> killed;
  for (int round = 0; round < 100; ++round) {
    bool any = false;
    for (const ProcessEntry& p : ListProcesses()) {
      if (p.ppid != self) continue;
      any = true;
      if (p.state == 'Z') continue;  // ended: reaped below
      SignalGroup(p.pid, SIGKILL);
      killed.insert(p.pid);
    }
    while (::waitpid(-1, nullptr, WNOHANG) > 0) {
    }
    if (!any) break;
    ::usleep(10000);
  }
  return static_cast<int>(killed.size());
}

long PosixProcessControl::PeakResidentBytes(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmHWM:", 0) == 0) {
      std::istringstream fields(line.substr(6));
      long kb = 0;
      fields >> kb;
      return kb * 1024;
    }
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------

Supervisor::Supervisor(SupervisorSpec spec, ProcessControl& control) : config_(spec.config), control_(control) {
  for (ProcessSpec& p : spec.processes) {
    Child c;
    c.spec = std::move(p);
    children_.push_back(std::move(c));
  }
}

Supervisor::Child* Supervisor::ByPid(int pid) {
  for (Child& c : children_) {
    if (c.pid && *c.pid == pid) return &c;
  }
  return nullptr;
}

void Supervisor::OnStatus(const std::string& process, int pid, double now) {
  for (Child& c : children_) {
    if (c.spec.name == process && c.pid && *c.pid == pid) c.last_status = now;
  }
}

void Supervisor::Down(Child& c, double now, const std::string& why, std::vector<std::string>* events) {
  const int pid = *c.pid;
  c.pid.reset();
  c.last_status.reset();
  if (now - c.started_at >= config_.healthy_after_s) c.backoff_level = 0;
  std::ostringstream os;
  os << c.spec.name << " (pid " << pid << ") " << why;
  if (c.restarts >= config_.max_restarts) {
    c.given_up = true;
    os << "; not restarted: " << c.restarts << " restarts already (max_restarts " << config_.max_restarts << ")";
  } else {
    const double wait =
        std::min(config_.backoff_max_s, config_.backoff_initial_s * std::pow(2.0, static_cast<double>(c.backoff_level)));
    c.backoff_level += 1;
    c.start_due = now + wait;
    os << "; restart " << c.restarts + 1 << " in " << FixedNumber(wait, 1) << " s";
  }
  events->push_back(os.str());
}

void Supervisor::OnOwnStatus(double now) { last_own_status_ = now; }

bool Supervisor::Hearing(double now, std::vector<std::string>* events) {
  const bool deaf = last_own_status_ && now - *last_own_status_ > config_.heartbeat_timeout_s;
  if (deaf && !deaf_) {
    events->push_back("hears no STATUS, its own included, for " + FixedNumber(now - *last_own_status_, 1) +
                      " s: its LCM reception stalls; no process is judged silent until it hears again");
  } else if (!deaf && deaf_) {
    events->push_back("hears STATUS again: every process gets a fresh " + FixedNumber(config_.heartbeat_timeout_s, 1) +
                      " s to answer");
    for (Child& c : children_) {
      if (!c.pid) continue;
      if (c.last_status) {
        c.last_status = now;
      } else {  // not answered yet: at least heartbeat_timeout_s more before it counts as never answering
        c.started_at = std::max(c.started_at, now - config_.startup_timeout_s + config_.heartbeat_timeout_s);
      }
    }
  }
  deaf_ = deaf;
  return !deaf;
}

std::vector<std::string> Supervisor::Step(double now) {
  std::vector<std::string> events;
  while (const std::optional<ProcessExit> e = control_.Reap()) {
    if (Child* c = ByPid(e->pid)) Down(*c, now, "died: " + e->how, &events);
  }
  const bool hearing = Hearing(now, &events);
  for (Child& c : children_) {
    if (!c.pid || !hearing) continue;
    const bool silent = c.last_status ? now - *c.last_status > config_.heartbeat_timeout_s
                                      : now - c.started_at > config_.startup_timeout_s;
    if (!silent) continue;
    const std::string why =
        c.last_status ? "stopped answering: no STATUS for " + FixedNumber(now - *c.last_status, 1) + " s"
                      : "never answered: no STATUS within " + FixedNumber(config_.startup_timeout_s, 1) + " s of its start";
    control_.Kill(*c.pid);
    // The killed process is reaped (and ignored) by a later Step: its pid is no longer ours.
    Down(c, now, why + "; killed", &events);
  }
  for (Child& c : children_) {
    if (c.pid || c.given_up || now + 1e-9 < c.start_due) continue;
    const bool restart = c.ever_started;
    std::string header;
    if (restart) {
      c.restarts += 1;
      header = "=== supervisor: restart " + std::to_string(c.restarts) + " of " + c.spec.name;
    }
    try {
      c.pid = control_.Start(c.spec, header);
    } catch (const std::exception& e) {
      c.given_up = true;
      events.push_back(c.spec.name + " could not be started: " + e.what());
      continue;
    }
    c.started_at = now;
    c.ever_started = true;
    c.last_status.reset();
    events.push_back(c.spec.name + (restart ? " restarted" : " started") + " (pid " + std::to_string(*c.pid) + ")");
  }
  return events;
}

std::vector<std::string> Supervisor::StopAll(double (*clock)(), void (*sleep_s)(double)) {
  std::vector<std::string> lines;
  for (Child& c : children_) {
    if (c.pid) control_.Terminate(*c.pid);
  }
  const double deadline = clock() + config_.stop_grace_s;
  const auto running = [&] {
    return std::any_of(children_.begin(), children_.end(), [](const Child& c) { return c.pid.has_value(); });
  };
  while (running() && clock() < deadline) {
    while (const std::optional<ProcessExit> e = control_.Reap()) {
      if (Child* c = ByPid(e->pid)) c->pid.reset();
    }
    if (running()) sleep_s(0.02);
  }
  for (Child& c : children_) {
    if (!c.pid) continue;
    lines.push_back(c.spec.name + " (pid " + std::to_string(*c.pid) + ") did not stop within " +
                    FixedNumber(config_.stop_grace_s, 1) + " s of SIGTERM: killed");
    control_.Kill(*c.pid);
  }
  // Reap what was killed (a killed process ends at once; wait a little for the kernel).
  const double kill_deadline = clock() + 1.0;
  while (running() && clock() < kill_deadline) {
    while (const std::optional<ProcessExit> e = control_.Reap()) {
      if (Child* c = ByPid(e->pid)) c->pid.reset();
    }
    if (running()) sleep_s(0.01);
  }
  // Children given up on or killed for silence may still be reaped here.
  while (control_.Reap()) {
  }
  if (const int strays = control_.KillStrays(); strays > 0) {
    lines.push_back("killed " + std::to_string(strays) + " process(es) the supervised ones left behind outside their groups");
  }
  return lines;
}

std::vector<std::string> Supervisor::GivenUp() const {
  std::vector<std::string> out;
  for (const Child& c : children_) {
    if (c.given_up) out.push_back(c.spec.name);
  }
  return out;
}

int Supervisor::Restarts(const std::string& name) const {
  for (const Child& c : children_) {
    if (c.spec.name == name) return c.restarts;
  }
  throw InputError("supervisor: no process named '" + name + "'");
}

std::optional<int> Supervisor::Pid(const std::string& name) const {
  for (const Child& c : children_) {
    if (c.spec.name == name) return c.pid;
  }
  throw InputError("supervisor: no process named '" + name + "'");
}

std::string Supervisor::PeakMemory() const {
  std::string out;
  for (const Child& c : children_) {
    if (!c.pid) continue;
    const long bytes = control_.PeakResidentBytes(*c.pid);
    if (bytes <= 0) continue;
    out += (out.empty() ? "" : ", ") + c.spec.name + " " + FixedNumber(static_cast<double>(bytes) / (1024.0 * 1024.0), 1) + " MB";
  }
  return out;
}

}  // namespace rbcp::nodes
