#pragma once
/// What every program's main() shares: the common command-line options (LCM URL, config folder,
/// quiet, run time) and a top-level guard that turns any escaped exception into
/// "<program>: error: <reason>" and exit status 2.

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

#include "rbcp/core/config_dir.h"

namespace rbcp::cli {

struct CommonOptions {
  std::string lcm_url;          ///< "" = LCM_DEFAULT_URL or LCM's default
  std::string config_dir;       ///< holds robots/, scenarios/ and per-process yaml
  bool quiet = false;           ///< no per-input log lines on stderr
  double max_runtime_s = 0.0;   ///< stop after this long [s]; 0 = until SIGINT/SIGTERM
};

/// Adds --lcm-url, --config-dir, --quiet and --max-runtime: the options of a process on LCM.
void AddCommonOptions(CLI::App& app, CommonOptions& options);
/// Adds --config-dir and --quiet: the options of a program that talks no LCM.
void AddOfflineOptions(CLI::App& app, CommonOptions& options);

/// Runs `body` and returns its exit code; --help prints the help and returns 0, a bad argument
/// prints CLI11's message and returns 2, any other exception prints "<process>: error: <what>"
/// and returns 2.
int GuardedMain(const char* process, CLI::App& app, int argc, char** argv, const std::function<int()>& body);

/// Adds a program's description and options to `app`, parsed into `options`.
template <typename Options>
using AddOptionsFunction = void (*)(CLI::App& app, Options& options);
/// A program's work on its parsed options; returns the exit status.
template <typename Options>
using RunFunction = int (*)(const Options& options);

/// The main() of a program `name` (the prefix of its error messages): its command line parsed
/// into its Options, then its work on them, under GuardedMain.
template <typename Options>
int Main(const char* name, int argc, char** argv, AddOptionsFunction<Options> add_options, RunFunction<Options> run) {
  CLI::App app;
  Options options;
  add_options(app, options);
  return GuardedMain(name, app, argc, argv, [&] { return run(options); });
}

}  // namespace rbcp::cli
