// check_plan: verifies a contact plan (JSON) against its scenario and prints every violation.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <iostream>

#include "rbcp/core/config_dir.h"
#include "rbcp/core/error.h"
#include "rbcp/plan_checker/plan_checker.h"
#include "rbcp/plan_checker/plan_json.h"

int main(int argc, char** argv) {
  CLI::App app{"Checks a contact plan against its scenario: feet on contact surfaces, one leg per step, joints\n"
               "consistent with the feet, no collision, static stability, joint torques, support margin.\n"
               "Reads files; talks no LCM. Exit status: 0 the plan passes, 1 it violates a check, 2 bad input, 3 internal\n"
               "error."};
  std::string scenario_path, plan_path, config_dir = rbcp::DefaultConfigDir();
  bool json = false;
  app.add_option("--scenario", scenario_path, "scenario YAML")->required();
  app.add_option("--plan", plan_path, "plan JSON: an array of states or an object with 'states' ('-' = stdin)")
      ->required();
  app.add_option("--config-dir", config_dir, "folder with robots/, equilibrium.yaml and affordance.yaml "
                                             "(default: $RBCP_CONFIG_DIR, else the installed PREFIX/share/rbcp/config, "
                                             "else the checkout's config/)")
      ->capture_default_str();
  app.add_flag("--json", json, "print the report as one JSON object");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    const rbcp::Scenario scenario = rbcp::LoadScenario(scenario_path);
    const rbcp::ContactPlan plan = rbcp::LoadContactPlanFile(plan_path);
    const rbcp::PlanCheckReport report = rbcp::CheckPlanForScenario(config_dir, scenario, plan);
    if (json) {
      std::cout << rbcp::PlanCheckReportToJson(report).dump() << std::endl;
    } else {
      for (const auto& v : report.violations) std::cout << "state " << v.state << ": " << v.check << ": " << v.detail << "\n";
      if (static_cast<int>(report.violations.size()) < report.violation_count) {
        std::cout << "... and " << report.violation_count - static_cast<int>(report.violations.size()) << " more\n";
      }
      for (const auto& v : report.walk_violations) {
        std::cout << "state " << v.state << ": " << v.check << ": " << v.detail << "\n";
      }
      std::cout << scenario.name << ": " << report.Summary() << std::endl;
    }
    return report.ok ? 0 : 1;
  } catch (const rbcp::InputError& e) {
    std::cerr << "check_plan: error: " << e.what() << std::endl;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "check_plan: internal error: " << e.what() << std::endl;
    return 3;
  }
}
