// Integration: affordance_extractor runs as its own OS process and talks UDP multicast LCM.
// ctest runs this binary inside tools/netns-run (a private network namespace), and each run
// also picks its own port, so parallel tests never hear each other.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp_msgs/process_status_t.hpp"
#include "support/affordance_log.h"
#include "support/child_process.h"

namespace rbcp {
namespace {

const std::string kBin = RBCP_BIN_DIR;
const std::string kSrc = RBCP_SOURCE_DIR;

std::string UniqueUrl() {
  const int port = 7700 + static_cast<int>(getpid() % 1000);
  return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=2097152";
}

// Runs a command, returns (exit code, stdout+stderr).
std::pair<int, std::string> RunCommand(const std::string& cmd) {
  std::string out;
  FILE* pipe = popen((cmd + " 2>&1").c_str(), "r");
  if (!pipe) return {-1, ""};
  char buf[4096];
  while (fgets(buf, sizeof(buf), pipe)) out += buf;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class AffordanceProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    url_ = UniqueUrl();
    lcm_ = std::make_unique<lcm::LCM>(url_);
    ASSERT_TRUE(lcm_->good()) << "no multicast route for " << url_ << ": run inside tools/netns-run";
    affordances_ = std::make_unique<transport::LatestMessage<rbcp_msgs::affordance_set_t>>(*lcm_, channels::kAffordances);
    status_ = std::make_unique<transport::LatestMessage<rbcp_msgs::process_status_t>>(*lcm_, channels::kStatus);
    log_path_ = ::testing::TempDir() + "affordance_extractor_" + std::to_string(getpid()) + ".log";
    process_ = std::make_unique<testing::ChildProcess>(
        std::vector<std::string>{kBin + "/affordance_extractor", "--lcm-url", url_}, log_path_);
    ASSERT_TRUE(process_->started());
  }
  void TearDown() override {
    if (process_) {
      EXPECT_EQ(process_->Stop(), 0) << process_->Log();
    }
  }

  // Publishes `publish` every 200 ms (the process may still be starting) until `done` holds.
  bool PublishUntil(const std::function<void()>& publish, const std::function<bool()>& done, double timeout_s = 20.0) {
    const auto start = std::chrono::steady_clock::now();
    auto next = start;
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < timeout_s) {
      if (!process_->Running()) return false;
      if (std::chrono::steady_clock::now() >= next) {
        publish();
        next += std::chrono::milliseconds(200);
      }
      lcm_->handleTimeout(20);
      if (done()) return true;
    }
    return false;
  }

  std::string url_, log_path_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::unique_ptr<transport::LatestMessage<rbcp_msgs::affordance_set_t>> affordances_;
  std::unique_ptr<transport::LatestMessage<rbcp_msgs::process_status_t>> status_;
  std::unique_ptr<testing::ChildProcess> process_;
};

TEST_F(AffordanceProcess, AnswersTerrainWithTheSurfacesOfTheLibrary) {
  const Scenario scenario = LoadScenario(kSrc + "/config/scenarios/darpa_rubble.yaml");
  const auto terrain = transport::ToTerrainMsg(scenario.terrain_mesh, 123456, scenario.name);
  ASSERT_TRUE(PublishUntil([&] { lcm_->publish(channels::kTerrain, &terrain); }, [&] { return affordances_->HasNew(); }))
      << process_->Log();
  const auto got = affordances_->Take();
  EXPECT_EQ(got->utime, 123456);
  EXPECT_EQ(got->terrain_id, terrain.terrain_id) << "the surfaces name the terrain they come from";

  const auto config = AffordanceConfig::Load(YamlMap::LoadFile(kSrc + "/config/affordance.yaml"));
  const auto expected = transport::ToAffordanceMsg(AffordanceExtractor(config).Extract(scenario.terrain_mesh), 123456,
                                                       terrain.terrain_id);
  ASSERT_GT(expected.num_surfaces, 0);
  testing::ExpectSameSurfaces(*got, expected);
}

TEST_F(AffordanceProcess, MalformedTerrainFailsWithReasonAndTheProcessCarriesOn) {
  const Scenario scenario = LoadScenario(kSrc + "/config/scenarios/flat_ground.yaml");
  auto bad = transport::ToTerrainMsg(scenario.terrain_mesh, 1, scenario.name);
  bad.vertices[0][0] = std::numeric_limits<double>::quiet_NaN();
  auto failed = [&] {
    const auto& s = status_->Latest();
    return s && s->state == rbcp_msgs::process_status_t::FAILED && s->input_utime == 1;
  };
  ASSERT_TRUE(PublishUntil([&] { lcm_->publish(channels::kTerrain, &bad); }, failed)) << process_->Log();
  EXPECT_EQ(status_->Latest()->process, "affordance_extractor");
  EXPECT_EQ(status_->Latest()->reason, "terrain mesh: vertex 0 is not finite");

  const auto good = transport::ToTerrainMsg(scenario.terrain_mesh, 2, scenario.name);
  ASSERT_TRUE(PublishUntil([&] { lcm_->publish(channels::kTerrain, &good); },
                           [&] { return affordances_->Latest() && affordances_->Latest()->utime == 2; }))
      << process_->Log();
  EXPECT_TRUE(process_->Running());
  EXPECT_NE(process_->Log().find("failed on input utime 1: terrain mesh: vertex 0 is not finite"), std::string::npos)
      << process_->Log();
}

TEST_F(AffordanceProcess, ReplayedLogGivesTheRecordedSurfaces) {
  const auto events = testing::ReadLog(testing::AffordanceLogPath());
  const testing::RecordedPair recorded = testing::FindPair(events);
  ASSERT_FALSE(recorded.terrain.data.empty());
  const auto& bytes = recorded.terrain.data;
  ASSERT_TRUE(PublishUntil(
      [&] { lcm_->publish(channels::kTerrain, bytes.data(), static_cast<unsigned>(bytes.size())); },
      [&] { return affordances_->HasNew(); }))
      << process_->Log();
  testing::ExpectSameSurfaces(*affordances_->Take(), recorded.affordances);
}

TEST(AffordanceCommandLine, OnceJsonPrintsSurfacesAndTiming) {
  const auto [code, out] =
      RunCommand(kBin + "/affordance_extractor --scenario " + kSrc + "/config/scenarios/plinth.yaml --once --json");
  ASSERT_EQ(code, 0) << out;
  const auto json = nlohmann::json::parse(out);
  ASSERT_TRUE(json.contains("surfaces"));
  ASSERT_TRUE(json.contains("extract_ms"));
  EXPECT_GE(json["extract_ms"].get<double>(), 0.0);
  ASSERT_GE(json["surfaces"].size(), 7u) << "floors, six treads and the top";
  for (const auto& s : json["surfaces"]) {
    EXPECT_GE(s["vertices"].size(), 3u);
    EXPECT_EQ(s["normal"].size(), 3u);
    EXPECT_GT(s["area"].get<double>(), 0.0);
  }
}

TEST(AffordanceCommandLine, HelpAndBadInput) {
  auto [code, out] = RunCommand(kBin + "/affordance_extractor --help");
  EXPECT_EQ(code, 0);
  EXPECT_NE(out.find("--scenario"), std::string::npos);

  const std::string bad = ::testing::TempDir() + "bad_scenario.yaml";
  FILE* f = fopen(bad.c_str(), "w");
  ASSERT_NE(f, nullptr);
  fputs("name: x\nterrain: []\nstart: {position: [0, 0], yaw: 0}\ngoal: {position: [1, 0], yaw: 0}\nbogus: 1\n", f);
  fclose(f);
  std::tie(code, out) = RunCommand(kBin + "/affordance_extractor --scenario " + bad + " --once --json");
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("affordance_extractor: error: "), std::string::npos) << out;
  EXPECT_NE(out.find(bad), std::string::npos) << "the message names the file: " << out;
}

}  // namespace
}  // namespace rbcp
