// The check_plan program on plans written to files: exit status, output, error messages.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "flat_ground_plan.h"
#include "rbcp/plan_checker/plan_json.h"

namespace rbcp {
namespace {

struct RunResult {
  int status = -1;
  std::string out;  ///< standard output
  std::string err;  ///< standard error
};

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

class CheckPlanProgramTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("rbcp_check_plan_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  std::string Write(const std::string& name, const std::string& text) const {
    const auto path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }

  /// Runs check_plan with the arguments (shell-quoted by the caller where needed).
  RunResult Run(const std::string& args, const std::string& stdin_file = "") const {
    const auto out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    std::string command = std::string(RBCP_BIN_DIR) + "/check_plan " + args + " >" + out.string() + " 2>" +
                          err.string();
    if (!stdin_file.empty()) command += " <" + stdin_file;
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadText(out), ReadText(err)};
  }

  static std::string Scenario() { return "--scenario " + test::ScenarioPath("flat_ground"); }

  std::filesystem::path dir_;
  ContactPlan plan_ = test::BuildFlatGroundPlan(test::FlatGroundWorld::Get().robot);
};

TEST_F(CheckPlanProgramTest, ValidPlanPasses) {
  const std::string path = Write("plan.json", ContactPlanToJson(plan_).dump());
  const RunResult r = Run(Scenario() + " --plan " + path);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("flat_ground: plan passes: 9 states"), std::string::npos) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;
}

TEST_F(CheckPlanProgramTest, AcceptsThePlanScenarioObjectAndStandardInput) {
  const nlohmann::json document = {{"scenario", "flat_ground"},
                                   {"contact_ok", true},
                                   {"steps", 8},
                                   {"states", ContactPlanToJson(plan_)}};
  const std::string path = Write("result.json", document.dump(2));
  EXPECT_EQ(Run(Scenario() + " --plan " + path).status, 0);
  const RunResult r = Run(Scenario() + " --plan -", path);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
}

TEST_F(CheckPlanProgramTest, ConfigDirOptionAndEnvironment) {
  const std::string path = Write("plan.json", ContactPlanToJson(plan_).dump());
  EXPECT_EQ(Run(Scenario() + " --plan " + path + " --config-dir " + test::ConfigDir()).status, 0);
  const RunResult missing = Run(Scenario() + " --plan " + path + " --config-dir " + (dir_ / "nowhere").string());
  EXPECT_EQ(missing.status, 2) << missing.out << missing.err;
  EXPECT_NE(missing.err.find("check_plan: error: "), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find((dir_ / "nowhere").string()), std::string::npos) << missing.err;
  const RunResult env = Run(Scenario() + " --plan " + path);
  EXPECT_EQ(env.status, 0);
  const std::string with_env = "env RBCP_CONFIG_DIR=" + (dir_ / "nowhere").string() + " " + std::string(RBCP_BIN_DIR) +
                               "/check_plan " + Scenario() + " --plan " + path + " >/dev/null 2>&1";
  const int status = std::system(with_env.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
}

TEST_F(CheckPlanProgramTest, ViolatingPlanListsEveryViolation) {
  // State 2's base into the ground and state 5's joints off their feet.
  plan_.states[2].base_position.z() = 0.10;
  plan_.states[5].joints[1] += 0.1;
  const std::string path = Write("plan.json", ContactPlanToJson(plan_).dump());
  const RunResult r = Run(Scenario() + " --plan " + path);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("state 2: collision: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("state 2: fk: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("state 5: fk: LF joints"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("flat_ground: plan fails: "), std::string::npos) << r.out;
}

TEST_F(CheckPlanProgramTest, JsonReport) {
  plan_.states[5].joints[1] += 0.1;
  const std::string path = Write("plan.json", ContactPlanToJson(plan_).dump());
  const RunResult r = Run(Scenario() + " --plan " + path + " --json");
  EXPECT_EQ(r.status, 1) << r.err;
  const nlohmann::json report = nlohmann::json::parse(r.out);
  EXPECT_EQ(report["ok"], false);
  EXPECT_EQ(report["states"], 9);
  ASSERT_GE(report["violations"].size(), 1u);
  bool fk = false;
  for (const auto& v : report["violations"]) fk = fk || (v["state"] == 5 && v["check"] == "fk");
  EXPECT_TRUE(fk) << report.dump(2);
}

TEST_F(CheckPlanProgramTest, BadInputExitsTwoNamingTheFile) {
  const std::string good = Write("plan.json", ContactPlanToJson(plan_).dump());

  const std::string absent = (dir_ / "absent.json").string();
  RunResult r = Run(Scenario() + " --plan " + absent);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("check_plan: error: " + absent), std::string::npos) << r.err;

  const std::string malformed = Write("malformed.json", "[{\"base\": ");
  r = Run(Scenario() + " --plan " + malformed);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("check_plan: error: " + malformed + ": malformed JSON"), std::string::npos) << r.err;

  nlohmann::json short_joints = ContactPlanToJson(plan_);
  short_joints[3]["joints"].erase(0);
  const std::string wrong = Write("wrong.json", short_joints.dump());
  r = Run(Scenario() + " --plan " + wrong);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("check_plan: error: " + wrong + ": state 3: 'joints': expected an array of 12 numbers"),
            std::string::npos)
      << r.err;

  const std::string empty = Write("empty.json", "[]");
  r = Run(Scenario() + " --plan " + empty);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("expected at least one state"), std::string::npos) << r.err;

  const std::string no_scenario = (dir_ / "absent.yaml").string();
  r = Run("--scenario " + no_scenario + " --plan " + good);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("check_plan: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(no_scenario), std::string::npos) << r.err;

  EXPECT_EQ(Run("--plan " + good).status, 2);  // --scenario is required
  EXPECT_EQ(Run(Scenario()).status, 2);        // --plan is required
}

TEST_F(CheckPlanProgramTest, Help) {
  const RunResult r = Run("--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("--scenario"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--plan"), std::string::npos);
  EXPECT_NE(r.out.find("--config-dir"), std::string::npos);
  EXPECT_NE(r.out.find("--json"), std::string::npos);
}

}  // namespace
}  // namespace rbcp
