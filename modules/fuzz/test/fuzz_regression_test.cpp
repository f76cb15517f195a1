// The inputs the fuzz targets found (tests/fuzz_regressions/NAME/, one folder per entry) go through
// the same entries in the ordinary build: each must be accepted or rejected with the project's
// error, never escape with another exception or crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "rbcp/fuzz/fuzz_entries.h"

namespace rbcp::fuzz {
namespace {

namespace fs = std::filesystem;

const fs::path kRegressions = fs::path(RBCP_SOURCE_DIR) / "tests" / "fuzz_regressions";

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<fs::path> SortedFiles(const fs::path& dir) {
  std::vector<fs::path> files;
  if (fs::is_directory(dir)) {
    for (const auto& item : fs::directory_iterator(dir)) {
      if (item.is_regular_file()) files.push_back(item.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::string> EntryNames() {
  std::vector<std::string> names;
  for (const Entry& e : Entries()) names.emplace_back(e.name);
  return names;
}

TEST(FuzzEntries, TargetsFileListsEveryEntryInOrder) {
  // tools/fuzz and the fuzz build take their targets from targets.txt.
  std::istringstream lines(ReadBytes(fs::path(RBCP_SOURCE_DIR) / "modules" / "fuzz" / "targets.txt"));
  std::vector<std::string> listed;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string name, max_len;
    words >> name >> max_len;
    EXPECT_GT(std::atoi(max_len.c_str()), 0) << line;
    listed.push_back(name);
  }
  EXPECT_EQ(listed, EntryNames());
}

TEST(FuzzEntries, EveryRegressionFolderNamesAnEntry) {
  ASSERT_TRUE(fs::is_directory(kRegressions)) << kRegressions;
  for (const auto& item : fs::directory_iterator(kRegressions)) {
    if (!item.is_directory()) continue;
    EXPECT_NE(FindEntry(item.path().filename().string()), nullptr) << item.path();
  }
}

TEST(FuzzEntries, RejectionsCarryAReason) {
  for (const Entry& e : Entries()) {
    const Outcome empty = e.run(nullptr, 0);
    EXPECT_FALSE(empty.accepted) << e.name;
    EXPECT_FALSE(empty.reason.empty()) << e.name;
  }
}

TEST(FuzzEntries, PartRecordsAreLengthPrefixedAndTheLastIsCutAtTheEnd) {
  const std::vector<std::uint8_t> input = {3, 0, 'a', 'b', 'c', 0, 0, 9, 1, 'x'};
  const auto records = SplitPartRecords(input.data(), input.size());
  const std::vector<std::pair<std::size_t, std::size_t>> expected = {{2, 3}, {7, 0}, {9, 1}};
  EXPECT_EQ(records, expected);
  // Bytes that are no part are rejected with the assembler's reason.
  const Outcome outcome = FindEntry("lcm_message_part")->run(input.data(), input.size());
  EXPECT_FALSE(outcome.accepted);
  EXPECT_NE(outcome.reason.find("TERRAIN/PART"), std::string::npos) << outcome.reason;
}

class FuzzRegression : public ::testing::TestWithParam<std::string> {};

TEST_P(FuzzRegression, EveryInputIsAcceptedOrRejectedCleanly) {
  const Entry* entry = FindEntry(GetParam());
  ASSERT_NE(entry, nullptr);
  for (const fs::path& file : SortedFiles(kRegressions / GetParam())) {
    const std::string bytes = ReadBytes(file);
    try {
      const Outcome outcome = entry->run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      EXPECT_TRUE(outcome.accepted || !outcome.reason.empty()) << file;
      std::cout << file.filename().string() << ": " << (outcome.accepted ? "accepted" : "rejected: " + outcome.reason)
                << "\n";
    } catch (const std::exception& e) {
      ADD_FAILURE() << file << ": escaped with " << e.what();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Entries, FuzzRegression, ::testing::ValuesIn(EntryNames()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace rbcp::fuzz
