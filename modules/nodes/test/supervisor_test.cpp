#include "rbcp/nodes/supervisor.h"
#include "rbcp/nodes/supervisor_process.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "rbcp/test_support/error_of.h"

namespace rbcp::nodes {
namespace {

using rbcp::test_support::ErrorOf;

/// Records what the supervisor asks of the operating system; exits are queued by the test.
class FakeControl : public ProcessControl {
 public:
  int Start(const ProcessSpec& spec, const std::string& log_header) override {
    if (fail_starts) throw std::runtime_error("no such program");
    started.push_back(spec.name);
    headers.push_back(log_header);
    return next_pid++;
  }
  void Terminate(int pid) override { terminated.push_back(pid); }
  void Kill(int pid) override { killed.push_back(pid); }
  std::optional<ProcessExit> Reap() override {
    if (exits.empty()) return std::nullopt;
    ProcessExit e = exits.front();
    exits.pop_front();
    return e;
  }
  int next_pid = 100;
  bool fail_starts = false;
  std::vector<std::string> started, headers;
  std::vector<int> terminated, killed;
  std::deque<ProcessExit> exits;
};

SupervisorSpec TwoProcesses() {
  SupervisorSpec spec;
  spec.config.heartbeat_timeout_s = 2.0;
  spec.config.startup_timeout_s = 10.0;
  spec.config.backoff_initial_s = 0.5;
  spec.config.backoff_max_s = 2.0;
  spec.config.healthy_after_s = 30.0;
  spec.config.max_restarts = 3;
  spec.config.stop_grace_s = 1.0;
  spec.processes = {{"planner", {"/bin/planner"}, "/tmp/planner.log"}, {"sim", {"/bin/sim"}, "/tmp/sim.log"}};
  return spec;
}

bool Contains(const std::vector<std::string>& lines, const std::string& part) {
  for (const std::string& l : lines) {
    if (l.find(part) != std::string::npos) return true;
  }
  return false;
}

TEST(Supervisor, StartsEveryProcessOnItsFirstStep) {
  FakeControl control;
  Supervisor supervisor(TwoProcesses(), control);
  EXPECT_TRUE(control.started.empty());
  EXPECT_EQ(supervisor.Step(0.0), (std::vector<std::string>{"planner started (pid 100)", "sim started (pid 101)"}));
  EXPECT_EQ(control.started, (std::vector<std::string>{"planner", "sim"}));
  EXPECT_EQ(control.headers, (std::vector<std::string>{"", ""}));
  EXPECT_EQ(supervisor.Pid("planner"), 100);
  EXPECT_EQ(supervisor.Pid("sim"), 101);
  EXPECT_TRUE(supervisor.Step(1.0).empty());
  EXPECT_EQ(control.started.size(), 2u);
}

TEST(Supervisor, RestartsADeadProcessAfterABackOffThatDoublesUpToItsMaximum) {
  FakeControl control;
  Supervisor supervisor(TwoProcesses(), control);
  supervisor.Step(0.0);
  control.exits.push_back({100, "killed by signal 9 (Killed)"});
  std::vector<std::string> events = supervisor.Step(1.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0], "planner (pid 100) died: killed by signal 9 (Killed); restart 1 in 0.5 s");
  EXPECT_FALSE(supervisor.Pid("planner").has_value());
  EXPECT_TRUE(supervisor.Step(1.4).empty());  // still backing off
  events = supervisor.Step(1.5);
  EXPECT_EQ(events, (std::vector<std::string>{"planner restarted (pid 102)"}));
  EXPECT_EQ(control.headers.back(), "=== supervisor: restart 1 of planner");
  EXPECT_EQ(supervisor.Restarts("planner"), 1);
  EXPECT_EQ(supervisor.Restarts("sim"), 0);
  // Dying again soon after: twice the wait, then capped at backoff_max_s.
  control.exits.push_back({102, "exited with status 1"});
  EXPECT_TRUE(Contains(supervisor.Step(2.0), "restart 2 in 1.0 s"));
  supervisor.Step(3.0);
  control.exits.push_back({103, "exited with status 1"});
  EXPECT_TRUE(Contains(supervisor.Step(3.5), "restart 3 in 2.0 s"));
}

TEST(Supervisor, AHealthyRunResetsTheBackOff) {
  FakeControl control;
  Supervisor supervisor(TwoProcesses(), control);
  supervisor.Step(0.0);
  control.exits.push_back({100, "exited with status 1"});
  supervisor.Step(1.0);
  supervisor.Step(1.5);  // restart 1 (pid 102)
  for (double t = 2.0; t < 40.0; t += 1.0) supervisor.OnStatus("planner", 102, t);
  control.exits.push_back({102, "exited with status 1"});
  EXPECT_TRUE(Contains(supervisor.Step(40.0), "restart 2 in 0.5 s"));
}

TEST(Supervisor, NamesKillsAndRestartsAProcessThatStopsAnswering) {
  FakeControl control;
  Supervisor supervisor(TwoProcesses(), control);
  supervisor.Step(0.0);
  supervisor.OnStatus("planner", 100, 0.5);
  supervisor.OnStatus("sim", 101, 0.5);
  supervisor.OnStatus("sim", 101, 2.4);
  std::vector<std::string> events = supervisor.Step(2.4);
  EXPECT_TRUE(events.empty());
  events = supervisor.Step(2.6);  // planner silent for 2.1 s
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0], "planner (pid 100) stopped answering: no STATUS for 2.1 s; killed; restart 1 in 0.5 s");
  EXPECT_EQ(control.killed, (std::vector<int>{100}));
  // The killed instance is reaped later and ignored; its late STATUS does not count.
  control.exits.push_back({100, "killed by signal 9 (Killed)"});
  supervisor.OnStatus("planner", 100, 2.7);
  EXPECT_TRUE(supervisor.Step(2.8).empty());
  EXPECT_EQ(supervisor.Step(3.1), (std::vector<std::string>{"planner restarted (pid 102)"}));
}

TEST(Supervisor, ASupervisorThatDoesNotHearItselfJudgesNoProcessSilent) {
  FakeControl control;
  Supervisor supervisor(TwoProcesses(), control);
  supervisor.Step(0.0);
  supervisor.OnOwnStatus(0.5);
  supervisor.OnStatus("planner", 100, 0.5);
  supervisor.OnStatus("sim", 101, 0.5);
  // Nothing heard for 2.5 s, the supervisor's own STATUS included: its reception stalls.
  std::vector<std::string> events = supervisor.Step(3.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_TRUE(Contains(events, "hears no STATUS, its own included, for 2.5 s")) << events[0];
  EXPECT_TRUE(supervisor.Step(6.0).empty());
  EXPECT_TRUE(control.killed.empty());
  // Hearing again, each process gets a fresh heartbeat_timeout_s; then the silent one is named.
  supervisor.OnOwnStatus(6.5);
  events = supervisor.Step(6.5);
  EXPECT_TRUE(Contains(events, "hears STATUS again")) << (events.empty() ? "" : events[0]);
  supervisor.OnOwnStatus(8.0);
  supervisor.OnStatus("sim", 101, 8.0);
  EXPECT_TRUE(supervisor.Step(8.0).empty());
  supervisor.OnOwnStatus(8.6);
  events = supervisor.Step(8.6);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0], "planner (pid 100) stopped answering: no STATUS for 2.1 s; killed; restart 1 in 0.5 s");
  EXPECT_EQ(control.killed, (std::vector<int>{100}));
}

TEST(Supervisor, KillsAProcessThatNeverAnswersWithinTheStartupTimeout) {
  FakeControl control;
  Supervisor supervisor(TwoProcesses(), control);
  supervisor.Step(0.0);
  supervisor.OnStatus("sim", 101, 5.0);
  supervisor.OnStatus("sim", 101, 9.5);
  supervisor.OnStatus("other", 100, 9.5);  // another process's STATUS with the planner's pid
  EXPECT_TRUE(supervisor.Step(9.9).empty());
  const std::vector<std::string> events = supervisor.Step(10.1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0], "planner (pid 100) never answered: no STATUS within 10.0 s of its start; killed; restart 1 in 0.5 s");
}

TEST(Supervisor, GivesUpAfterMaxRestarts) {
  FakeControl control;
  SupervisorSpec spec = TwoProcesses();
  spec.config.max_restarts = 1;
  Supervisor supervisor(spec, control);
  supervisor.Step(0.0);
  control.exits.push_back({100, "exited with status 3"});
  supervisor.Step(1.0);
  supervisor.Step(2.0);  // restart 1: pid 102
  control.exits.push_back({102, "exited with status 3"});
  const std::vector<std::string> events = supervisor.Step(3.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0], "planner (pid 102) died: exited with status 3; not restarted: 1 restarts already (max_restarts 1)");
  EXPECT_EQ(supervisor.GivenUp(), (std::vector<std::string>{"planner"}));
  supervisor.Step(100.0);
  EXPECT_EQ(control.started.size(), 3u);
}

TEST(Supervisor, AProcessThatCannotStartIsGivenUpOnWithTheReason) {
  FakeControl control;
  control.fail_starts = true;
  Supervisor supervisor(TwoProcesses(), control);
  const std::vector<std::string> events = supervisor.Step(0.0);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0], "planner could not be started: no such program");
  EXPECT_EQ(events[1], "sim could not be started: no such program");
  EXPECT_EQ(supervisor.GivenUp().size(), 2u);
}

double g_fake_time = 0.0;
double FakeClock() { return g_fake_time; }
void FakeSleep(double s) { g_fake_time += s; }

TEST(Supervisor, StopAllTerminatesEveryProcessAndKillsThoseThatDoNotStop) {
  FakeControl control;
  Supervisor supervisor(TwoProcesses(), control);
  supervisor.Step(0.0);
  control.exits.push_back({101, "exited with status 0"});  // the sim stops on SIGTERM
  g_fake_time = 10.0;
  const std::vector<std::string> lines = supervisor.StopAll(&FakeClock, &FakeSleep);
  EXPECT_EQ(control.terminated, (std::vector<int>{100, 101}));
  EXPECT_EQ(control.killed, (std::vector<int>{100}));
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "planner (pid 100) did not stop within 1.0 s of SIGTERM: killed");
  EXPECT_GE(g_fake_time, 11.0);
}

TEST(SupervisorSpec, LoadsStrictlyWithClearErrors) {
  const std::string ok =
      "{heartbeat_timeout_s: 2, startup_timeout_s: 60, backoff_initial_s: 0.5, backoff_max_s: 8, healthy_after_s: 30,"
      " max_restarts: 10, stop_grace_s: 3, processes: [{name: sim, command: [/bin/sim, --replan], log: /tmp/sim.log}]}";
  const SupervisorSpec spec = SupervisorSpec::Load(YamlMap(YAML::Load(ok), "spec.yaml"));
  ASSERT_EQ(spec.processes.size(), 1u);
  EXPECT_EQ(spec.processes[0].command, (std::vector<std::string>{"/bin/sim", "--replan"}));
  EXPECT_EQ(spec.config.max_restarts, 10);
  const auto error = [](const std::string& text) {
    return ErrorOf([&] { SupervisorSpec::Load(YamlMap(YAML::Load(text), "spec.yaml")); });
  };
  std::string text = ok;
  text.replace(text.find("backoff_max_s: 8"), 16, "backoff_max_s: 0.1");
  EXPECT_EQ(error(text), "spec.yaml: 'backoff_max_s': expected at least backoff_initial_s (0.5), got 0.1");
  text = ok;
  text.replace(text.find("command: [/bin/sim, --replan]"), 29, "command: []");
  EXPECT_EQ(error(text), "spec.yaml: processes[0]: 'command': expected a program and its arguments");
  text = ok;
  text.replace(text.find("log: /tmp/sim.log}"), 18, "log: /tmp/sim.log, extra: 1}");
  EXPECT_EQ(error(text), "spec.yaml: processes[0]: 'extra': unknown key");
  text = ok;
  text.replace(text.find("processes: ["), 12, "processes: [{name: sim, command: [a], log: b}, ");
  EXPECT_EQ(error(text), "spec.yaml: processes[1]: 'name': process 'sim' is listed twice");
  // Bounded waits and back-offs: no hang on stop, no restart loop that spins.
  text = ok;
  text.replace(text.find("stop_grace_s: 3"), 15, "stop_grace_s: 1e300");
  EXPECT_EQ(error(text), "spec.yaml: 'stop_grace_s': expected a number in [0.01, 60] [s], got 1e+300");
  text = ok;
  text.replace(text.find("backoff_initial_s: 0.5"), 22, "backoff_initial_s: 1e-9");
  EXPECT_EQ(error(text), "spec.yaml: 'backoff_initial_s': expected a number in [0.01, 3600] [s], got 1e-09");
  // A name with a control character is rejected, escaped.
  text = ok;
  text.replace(text.find("name: sim"), 9, "name: \"s\\x1b[2Jim\"");
  EXPECT_EQ(error(text),
            "spec.yaml: processes[0]: 'name': expected at most 64 letters, digits, '_', '.', '-' or '@', got "
            "'s\\x1b[2Jim'");
}

TEST(PosixSupervisor, ALogThatIsNotARegularFileIsRefusedWithoutBlocking) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("rbcp_supervisor_f" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string fifo = (dir / "log.fifo").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  PosixProcessControl control;
  try {
    control.Start({"sleeper", {"/bin/sleep", "30"}, fifo}, "");
    ADD_FAILURE() << "a FIFO log was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is not a regular file"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// Each host of a split pipeline runs its own supervisor; their STATUS names tell them apart, and
// the operator takes any of them for a supervisor.
TEST(SupervisorName, NamesTheHostAndIsRecognised) {
  EXPECT_EQ(SupervisorName(""), "supervisor");
  EXPECT_EQ(SupervisorName("robot"), "supervisor@robot");
  EXPECT_TRUE(IsSupervisorName("supervisor"));
  EXPECT_TRUE(IsSupervisorName("supervisor@operator"));
  EXPECT_FALSE(IsSupervisorName("supervisor@"));
  EXPECT_FALSE(IsSupervisorName("supervisors"));
  EXPECT_FALSE(IsSupervisorName("contact_planner"));
  EXPECT_EQ(ErrorOf([] { SupervisorName("robot 1"); }),
            "supervisor: expected a host name of letters, digits, _ and -, got 'robot 1'");
}

// Real processes: a child that ignores SIGTERM is killed, a stopped one is stopped, nothing is
// left behind, and the log holds the child's output.

/// Processes of the process group `pgid` that are not zombies (a zombie has ended; whoever
/// inherited it reaps it in its own time).
int LiveMembers(int pgid) {
  int live = 0;
  for (const ProcessEntry& p : ListProcesses()) {
    if (p.pgrp == pgid && p.state != 'Z') ++live;
  }
  return live;
}

bool Alive(int pid) { return ::kill(pid, 0) == 0 || errno != ESRCH; }

double WallClock() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
void WallSleep(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

TEST(PosixSupervisor, StopsEveryChildAStoppedAndAStubbornOneIncluded) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("rbcp_supervisor_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  SupervisorSpec spec;
  spec.config.stop_grace_s = 1.0;
  spec.processes = {
      {"polite", {"/bin/sh", "-c", "echo started; exec sleep 30"}, (dir / "polite.log").string()},
      {"stubborn", {"/bin/sh", "-c", "trap '' TERM; echo started; while :; do sleep 0.05; done"}, (dir / "stubborn.log").string()},
      {"stopped", {"/bin/sleep", "30"}, (dir / "stopped.log").string()},
  };
  PosixProcessControl control;
  Supervisor supervisor(spec, control);
  supervisor.Step(WallClock());
  const int polite = *supervisor.Pid("polite");
  const int stubborn = *supervisor.Pid("stubborn");
  const int stopped = *supervisor.Pid("stopped");
  // Each shell has set itself up (the stubborn one ignores SIGTERM) once it said so in its log.
  const auto said_started = [&](const char* name) {
    std::ifstream in(dir / name);
    std::string line;
    return std::getline(in, line) && line == "started";
  };
  for (int i = 0; i < 1000 && !(said_started("polite.log") && said_started("stubborn.log")); ++i) WallSleep(0.01);
  ASSERT_TRUE(said_started("polite.log") && said_started("stubborn.log"));
  ASSERT_EQ(::kill(stopped, SIGSTOP), 0);
  const std::vector<std::string> lines = supervisor.StopAll(&WallClock, &WallSleep);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("stubborn"), std::string::npos) << lines[0];
  EXPECT_FALSE(Alive(polite));
  EXPECT_FALSE(Alive(stubborn));
  EXPECT_FALSE(Alive(stopped));
  // The stubborn shell's own children got the same SIGKILL; one that was not the supervisor's
  // child ends when the kernel gets to it, which on a loaded machine takes a moment.
  for (int i = 0; i < 500 && LiveMembers(stubborn) > 0; ++i) WallSleep(0.01);
  EXPECT_EQ(LiveMembers(stubborn), 0) << "the stubborn shell's own children are gone too";
  std::filesystem::remove_all(dir);
}

TEST(PosixSupervisor, WhatAChildLeftBehindInASessionOfItsOwnIsStoppedToo) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("rbcp_supervisor_s" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string grandchild_pid = (dir / "grandchild.pid").string();
  SupervisorSpec spec;
  spec.config.stop_grace_s = 1.0;
  // The shell starts a grandchild in a new session (out of the shell's process group, which is
  // what the supervisor signals), says so, and waits.
  spec.processes = {{"spawner",
                     {"/bin/sh", "-c", "setsid sleep 300 & echo $! > " + grandchild_pid + "; wait"},
                     (dir / "spawner.log").string()}};
  PosixProcessControl control;
  Supervisor supervisor(spec, control);
  supervisor.Step(WallClock());
  const int spawner = *supervisor.Pid("spawner");
  int grandchild = 0;
  for (int i = 0; i < 500 && grandchild == 0; ++i) {
    std::ifstream in(grandchild_pid);
    if (!(in >> grandchild)) grandchild = 0;
    if (grandchild == 0) WallSleep(0.01);
  }
  ASSERT_GT(grandchild, 0);
  // The grandchild is in a group of its own once setsid has run.
  for (int i = 0; i < 500 && ::getpgid(grandchild) != grandchild; ++i) WallSleep(0.01);
  ASSERT_EQ(::getpgid(grandchild), grandchild);
  const std::vector<std::string> lines = supervisor.StopAll(&WallClock, &WallSleep);
  EXPECT_FALSE(Alive(spawner));
  EXPECT_FALSE(Alive(grandchild)) << "the grandchild outlived its supervisor";
  EXPECT_TRUE(Contains(lines, "killed 1 process(es) the supervised ones left behind")) << ::testing::PrintToString(lines);
  std::filesystem::remove_all(dir);
}

TEST(PosixSupervisor, RestartsAChildKilledFromOutside) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("rbcp_supervisor_k" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  SupervisorSpec spec;
  spec.config.backoff_initial_s = 0.05;
  spec.config.stop_grace_s = 1.0;
  spec.processes = {{"sleeper", {"/bin/sleep", "30"}, (dir / "sleeper.log").string()}};
  PosixProcessControl control;
  Supervisor supervisor(spec, control);
  supervisor.Step(WallClock());
  const int first = *supervisor.Pid("sleeper");
  ASSERT_EQ(::kill(first, SIGKILL), 0);
  std::vector<std::string> events;
  const double deadline = WallClock() + 5.0;
  while (WallClock() < deadline && (!supervisor.Pid("sleeper") || *supervisor.Pid("sleeper") == first)) {
    for (std::string& e : supervisor.Step(WallClock())) events.push_back(std::move(e));
    WallSleep(0.01);
  }
  ASSERT_TRUE(supervisor.Pid("sleeper").has_value());
  EXPECT_NE(*supervisor.Pid("sleeper"), first);
  EXPECT_TRUE(Contains(events, "died: killed by signal 9"));
  EXPECT_EQ(supervisor.Restarts("sleeper"), 1);
  supervisor.StopAll(&WallClock, &WallSleep);
  std::ifstream log(dir / "sleeper.log");
  std::string line;
  std::getline(log, line);
  EXPECT_EQ(line, "=== supervisor: restart 1 of sleeper");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rbcp::nodes
