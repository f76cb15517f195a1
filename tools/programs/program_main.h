#pragma once
/// The main() of an operator or test program: its command line parsed into its Options, then its
/// work on them, under nodes::GuardedMain (--help prints the help and exits 0; a bad argument, or
/// an error that escapes the work, exits 2).

#include <CLI/CLI.hpp>

#include "rbcp/nodes/process.h"

namespace rbcp::programs {

/// Adds the program's description and options to `app`, parsed into `options`.
template <typename Options>
using AddOptionsFunction = void (*)(CLI::App& app, Options& options);
/// The program's work on its parsed options; returns the exit status.
template <typename Options>
using RunFunction = int (*)(const Options& options);

/// Runs the program `name` (the prefix of its error messages).
template <typename Options>
int Main(const char* name, int argc, char** argv, AddOptionsFunction<Options> add_options, RunFunction<Options> run) {
  CLI::App app;
  Options options;
  add_options(app, options);
  return nodes::GuardedMain(name, app, argc, argv, [&] { return run(options); });
}

}  // namespace rbcp::programs
