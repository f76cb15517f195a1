#include "rbcp/cli/cli.h"

#include <cstdio>
#include <exception>

namespace rbcp::cli {

void AddOfflineOptions(CLI::App& app, CommonOptions& options) {
  options.config_dir = DefaultConfigDir();
  app.add_option("--config-dir", options.config_dir,
                 "folder with robots/, scenarios/ and process yaml (default: $RBCP_CONFIG_DIR, else the installed "
                 "PREFIX/share/rbcp/config, else the checkout's config/)")
      ->capture_default_str();
  app.add_flag("--quiet", options.quiet, "do not log every handled input on stderr");
}

void AddCommonOptions(CLI::App& app, CommonOptions& options) {
  app.add_option("--lcm-url", options.lcm_url, "LCM URL (default: $LCM_DEFAULT_URL or LCM's default udpm)");
  AddOfflineOptions(app, options);
  app.add_option("--max-runtime", options.max_runtime_s, "stop after this many seconds (0: run until SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber);
}

int GuardedMain(const char* process, CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help is 0; a bad argument is bad input
  }
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", process, e.what());
    return 2;
  }
}

}  // namespace rbcp::cli
