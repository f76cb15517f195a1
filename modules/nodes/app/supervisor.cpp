// supervisor: keeps the pipeline's processes running (restart with back-off, silent ones named
// and restarted) and stops them all, a hung one included, on SIGINT or SIGTERM.
#include "rbcp/cli/cli.h"
#include "rbcp/nodes/supervisor_process.h"
#include "rbcp/transport/run_loop.h"

namespace {

using namespace rbcp;

struct Options {
  cli::CommonOptions common;
  std::string spec_path, host;
};

void AddOptions(CLI::App& app, Options& o) {
  app.description(
      "Supervisor: starts the processes of a spec file, restarts one that dies (the back-off doubles with\n"
      "every restart in a row) or stops publishing STATUS (heartbeat_timeout_s), and on SIGINT/SIGTERM\n"
      "stops them all (SIGTERM, then SIGKILL after stop_grace_s). Publishes its events on STATUS as\n"
      "process \"supervisor\" (\"supervisor@HOST\" with --host). Exit status: 0 stopped, 1 a process was given\n"
      "up on, 2 bad input.");
  cli::AddCommonOptions(app, o.common);
  app.add_option("--spec", o.spec_path,
                 "YAML: heartbeat_timeout_s, startup_timeout_s, backoff_initial_s, backoff_max_s, healthy_after_s,\n"
                 "max_restarts, stop_grace_s, processes: [{name, command: [program, args...], log}]")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--host", o.host,
                 "the host it supervises, when each host of a pipeline split over several runs its own supervisor:\n"
                 "its STATUS comes as process supervisor@HOST (letters, digits, _ and -)");
}

int Run(const Options& o) {
  const std::string name = nodes::SupervisorName(o.host);
  const nodes::SupervisorSpec spec = nodes::SupervisorSpec::LoadFile(o.spec_path);
  auto lcm = transport::OpenLcm(o.common.lcm_url);
  return nodes::RunSupervisor(spec, *lcm, name, !o.common.quiet, o.common.max_runtime_s);
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main(rbcp::nodes::kSupervisorName, argc, argv, AddOptions, Run); }
