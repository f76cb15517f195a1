#include "rbcp/offline_pipeline/offline_pipeline.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/plan_checker/plan_checker.h"
#include "rbcp/plan_checker/plan_json.h"

namespace rbcp {
namespace {

const std::string kConfig = std::string(RBCP_SOURCE_DIR) + "/config";

TEST(OfflinePipeline, RootStageOnFlatGroundGivesAStablePathAndJson) {
  const OfflinePipeline pipeline(kConfig);
  const Scenario scenario = LoadScenario(kConfig + "/scenarios/flat_ground.yaml");
  const PipelineResult a = pipeline.Run(scenario, PipelineStage::kRoot, 4, 5.0);
  ASSERT_TRUE(a.ok()) << a.failure;
  ASSERT_TRUE(a.root.has_value());
  const auto json = ToJson(a);
  for (const char* key : {"affordance_ms", "root_ok", "root_s", "root_path", "failure"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_TRUE(json["root_ok"].get<bool>());
  EXPECT_TRUE(json["failure"].is_null());
  const auto& first = json["root_path"].front();
  EXPECT_EQ(first["position"].size(), 3u);
  EXPECT_EQ(first["velocity"].size(), 3u);
  EXPECT_TRUE(first.contains("t") && first.contains("yaw"));

  const PipelineResult b = pipeline.Run(scenario, PipelineStage::kRoot, 4, 5.0);
  ASSERT_EQ(a.root->samples.size(), b.root->samples.size());
  for (std::size_t i = 0; i < a.root->samples.size(); ++i) {
    EXPECT_EQ(a.root->samples[i].p, b.root->samples[i].p) << "same seed, same path";
  }
}

TEST(OfflinePipeline, AGuideNoContactPlanFollowsIsReplacedByTheNext) {
  // A contact search bounded to a handful of evaluations follows no guide: each of the
  // guide_retries (2) next guides is tried, then the run fails with the last guide's reason.
  const auto dir = std::filesystem::temp_directory_path() / ("rbcp_guides_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::copy(kConfig, dir, std::filesystem::copy_options::recursive);
  {
    std::ifstream in(dir / "contact_planner.yaml");
    std::stringstream text;
    text << in.rdbuf();
    std::string yaml = text.str();
    const std::string key = "max_evaluations: 3000000";
    ASSERT_NE(yaml.find(key), std::string::npos);
    yaml.replace(yaml.find(key), key.size(), "max_evaluations: 20");
    std::ofstream(dir / "contact_planner.yaml") << yaml;
  }
  const OfflinePipeline pipeline(dir.string());
  const Scenario scenario = LoadScenario(kConfig + "/scenarios/flat_ground.yaml");
  const PipelineResult r = pipeline.Run(scenario, PipelineStage::kContact, 4, 5.0);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(r.failure.rfind("contact: no_foothold", 0), 0u) << r.failure;
  ASSERT_EQ(r.failed_guides.size(), 2u);
  EXPECT_EQ(r.failed_guides[0].rfind("seed " + std::to_string(GuideSeed(4, 0)) + ": no_foothold", 0), 0u)
      << r.failed_guides[0];
  EXPECT_EQ(r.failed_guides[1].rfind("seed " + std::to_string(GuideSeed(4, 1)) + ": no_foothold", 0), 0u)
      << r.failed_guides[1];
  EXPECT_EQ(GuideSeed(4, 0), 4u);
  EXPECT_NE(GuideSeed(4, 1), GuideSeed(5, 0));
  EXPECT_GE(r.contact_total_s, r.contact->planning_time_s);
  const auto json = ToJson(r);
  EXPECT_EQ(json["failed_guides"].size(), 2u);
  EXPECT_FALSE(json["contact_ok"].get<bool>());
}

TEST(OfflinePipeline, AffordanceStageOnlyAndBadStageName) {
  const OfflinePipeline pipeline(kConfig);
  const PipelineResult r =
      pipeline.Run(LoadScenario(kConfig + "/scenarios/plinth.yaml"), PipelineStage::kAffordance, 1, 1.0);
  EXPECT_TRUE(r.ok());
  EXPECT_FALSE(r.root.has_value());
  EXPECT_FALSE(ToJson(r).contains("root_ok"));
  EXPECT_THROW(ParseStage("contacts"), InputError);
  EXPECT_EQ(ParseStage("contact"), PipelineStage::kContact);
}

TEST(OfflinePipeline, ContactStageOnFlatGroundGivesACheckedPlanInJson) {
  const OfflinePipeline pipeline(kConfig);
  const Scenario scenario = LoadScenario(kConfig + "/scenarios/flat_ground.yaml");
  const PipelineResult r = pipeline.Run(scenario, PipelineStage::kContact, 4, 5.0);
  ASSERT_TRUE(r.ok()) << r.failure;
  ASSERT_TRUE(r.root.has_value());
  ASSERT_TRUE(r.contact.has_value());
  EXPECT_TRUE(r.contact->reached_goal);

  // Round trip through text, as plan_scenario prints it and check_plan reads it.
  const auto json = nlohmann::json::parse(ToJson(r).dump());
  for (const char* key : {"affordance_ms", "root_ok", "root_s", "root_path", "contact_ok", "contact_s", "steps",
                          "states", "failure"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_TRUE(json["root_ok"].get<bool>());
  EXPECT_TRUE(json["contact_ok"].get<bool>());
  EXPECT_TRUE(json["failure"].is_null());
  ASSERT_FALSE(json["states"].empty());
  EXPECT_EQ(json["steps"].get<int>(), static_cast<int>(json["states"].size()) - 1);
  const auto& first = json["states"].front();
  EXPECT_EQ(first["base"]["position"].size(), 3u);
  EXPECT_EQ(first["base"]["rpy"].size(), 3u);
  EXPECT_EQ(first["joints"].size(), 12u);
  EXPECT_EQ(first["feet"].size(), 4u);
  EXPECT_TRUE(first["moving_leg"].is_null());

  const ContactPlan plan = ContactPlanFromJson(json["states"]);
  ASSERT_EQ(plan.states.size(), r.contact->plan.states.size());
  for (std::size_t i = 0; i < plan.states.size(); ++i) {
    EXPECT_EQ(plan.states[i].base_position, r.contact->plan.states[i].base_position) << i;
    EXPECT_EQ(plan.states[i].joints, r.contact->plan.states[i].joints) << i;
  }
  const PlanCheckReport report = CheckPlanForScenario(kConfig, scenario, plan);
  EXPECT_TRUE(report.ok) << report.Summary();

  const PipelineResult again = pipeline.Run(scenario, PipelineStage::kContact, 4, 5.0);
  ASSERT_TRUE(again.contact.has_value());
  ASSERT_EQ(again.contact->plan.states.size(), plan.states.size()) << "same seed, same plan";
  for (std::size_t i = 0; i < plan.states.size(); ++i) {
    EXPECT_EQ(again.contact->plan.states[i].feet[0].position, r.contact->plan.states[i].feet[0].position) << i;
  }
}

TEST(OfflinePipeline, RootFailureLeavesTheContactKeysEmpty) {
  PipelineResult r;
  r.stage = PipelineStage::kContact;
  r.failure = "root: no terrain under the goal";
  const auto json = ToJson(r);
  EXPECT_FALSE(json["contact_ok"].get<bool>());
  EXPECT_TRUE(json["states"].empty());
  EXPECT_EQ(json["failure"], "root: no terrain under the goal");
}

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// Runs a shell command; returns its exit status (-1 if it did not exit).
int RunCommand(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OfflinePipeline, CheckPlanAcceptsThePlanPrintedByPlanScenario) {
  const auto dir = std::filesystem::temp_directory_path() / ("rbcp_plan_scenario_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string bin = RBCP_BIN_DIR;
  const std::string scenario = kConfig + "/scenarios/flat_ground.yaml";
  const auto plan = dir / "plan.json", err = dir / "err.txt", report = dir / "report.txt";
  ASSERT_EQ(RunCommand(bin + "/plan_scenario --scenario " + scenario + " --stage contact --json >" + plan.string() + " 2>" +
                err.string()),
            0)
      << ReadText(plan) << ReadText(err);
  const auto json = nlohmann::json::parse(ReadText(plan));
  EXPECT_TRUE(json["contact_ok"].get<bool>()) << json["failure"];
  EXPECT_EQ(RunCommand(bin + "/check_plan --scenario " + scenario + " --plan " + plan.string() + " >" + report.string() +
                " 2>" + err.string()),
            0)
      << ReadText(report) << ReadText(err);
  EXPECT_NE(ReadText(report).find("flat_ground: plan passes"), std::string::npos) << ReadText(report);
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

}  // namespace
}  // namespace rbcp
