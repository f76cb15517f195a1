// run_recorder: records every LCM message of a run to an LCM log file (lcm-logger's format), with
// a receive queue deep enough that a burst of robot states does not crowd out a plan.
//
// LCM keeps at most a fixed number of received messages per subscription (30 by default) and
// drops the next ones until the subscriber takes them; a recorder subscribed to every channel at
// once meets that bound within milliseconds of a robot state stream at several hundred hertz of
// simulated time, whenever it is not scheduled for a moment, and then loses whatever comes
// meanwhile, a contact plan included. This recorder raises the bound (--queue-capacity) and
// flushes the file on a short period, so that a log follower (live_bridge --follow-log) sees it
// grow.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <lcm/lcm-cpp.hpp>

#include "rbcp/cli/cli.h"
#include "rbcp/core/error.h"
#include "rbcp/transport/run_loop.h"

namespace {

using namespace rbcp;
using Clock = std::chrono::steady_clock;

struct Options {
  cli::CommonOptions common;
  std::string out_path;
  std::string channels = ".*";
  bool force = false;
  int queue_capacity = 100000;
  int flush_interval_ms = 100;
};

void AddOptions(CLI::App& app, Options& o) {
  app.description(
      "Records every message on LCM to an LCM log file (the format lcm-logger writes, which lcm-logplayer,\n"
      "run_log, replay_log and tools/view read) until SIGINT or SIGTERM, with a deep receive queue so that no\n"
      "message is lost while the recorder waits for the processor. Exit status: 0 recorded, 2 bad input.");
  cli::AddCommonOptions(app, o.common);
  app.add_option("out", o.out_path, "the log file to write")->required();
  app.add_flag("--force", o.force, "overwrite the file when it exists");
  app.add_option("--channel", o.channels, "the channels to record (a regular expression)")->capture_default_str();
  app.add_option("--queue-capacity", o.queue_capacity,
                 "received messages kept for the recorder before LCM drops the next ones")
      ->capture_default_str()->check(CLI::Range(30, 10000000));
  app.add_option("--flush-interval-ms", o.flush_interval_ms, "the file is flushed to disk this often [ms]")
      ->capture_default_str()->check(CLI::Range(1, 60000));
}

/// Writes each received message to the log, timestamped with its receive time. A failed write is
/// noted, not thrown: the handler runs inside LCM's C code.
struct Recorder {
  lcm::LogFile& log;
  long events = 0;
  bool write_failed = false;

  void Write(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    lcm::LogEvent event{};
    event.timestamp = rbuf->recv_utime;
    event.channel = channel;
    event.datalen = static_cast<int32_t>(rbuf->data_size);
    event.data = rbuf->data;
    if (log.writeEvent(&event) != 0) {
      write_failed = true;
      return;
    }
    events += 1;
  }
  static void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Recorder* recorder) {
    recorder->Write(rbuf, channel);
  }
};

int Run(const Options& o) {
  if (!o.force && std::filesystem::exists(o.out_path)) {
    throw InputError(o.out_path + " exists (--force overwrites it)");
  }
  lcm::LogFile log(o.out_path, "w");
  if (!log.good()) throw InputError("cannot open " + o.out_path + " for writing");
  auto lcm = transport::OpenLcm(o.common.lcm_url);
  Recorder recorder{log};
  lcm::Subscription* subscription = lcm->subscribeFunction(o.channels, &Recorder::Handle, &recorder);
  subscription->setQueueCapacity(o.queue_capacity);
  transport::InstallStopHandlers();
  if (!o.common.quiet) std::cerr << "[run_recorder] recording " << o.channels << " to " << o.out_path << "\n";
  const auto start = Clock::now();
  auto next_flush = start;
  while (!transport::StopRequested()) {
    lcm->handleTimeout(o.flush_interval_ms);
    if (recorder.write_failed) throw InputError("cannot write " + o.out_path + " (is the disk full?)");
    const auto now = Clock::now();
    if (now >= next_flush) {
      std::fflush(log.getFilePtr());
      next_flush = now + std::chrono::milliseconds(o.flush_interval_ms);
    }
    if (o.common.max_runtime_s > 0 && std::chrono::duration<double>(now - start).count() > o.common.max_runtime_s) break;
  }
  // What arrived before the stop is written too.
  while (lcm->handleTimeout(0) > 0) {
  }
  std::fflush(log.getFilePtr());
  if (!o.common.quiet) std::cerr << "[run_recorder] " << recorder.events << " messages in " << o.out_path << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("run_recorder", argc, argv, AddOptions, Run); }
