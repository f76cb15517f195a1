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

TEST(FuzzEntries, EverySeedIsAccepted) {
  // tests/fuzz_seeds/NAME/ holds valid inputs of the targets whose seeds are not project files.
  const fs::path seeds = fs::path(RBCP_SOURCE_DIR) / "tests" / "fuzz_seeds";
  int checked = 0;
  for (const auto& folder : fs::directory_iterator(seeds)) {
    if (!folder.is_directory()) continue;
    const Entry* entry = FindEntry(folder.path().filename().string());
    ASSERT_NE(entry, nullptr) << folder.path();
    for (const fs::path& file : SortedFiles(folder.path())) {
      const std::string bytes = ReadBytes(file);
      const Outcome outcome = entry->run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      EXPECT_TRUE(outcome.accepted) << file << ": " << outcome.reason;
      ++checked;
    }
  }
  EXPECT_GE(checked, 4);
  const std::string events = ReadBytes(fs::path(RBCP_SOURCE_DIR) / "tests" / "data" / "box_drop_events.yaml");
  const Outcome outcome =
      FindEntry("world_events")->run(reinterpret_cast<const std::uint8_t*>(events.data()), events.size());
  EXPECT_TRUE(outcome.accepted) << outcome.reason;
}

/// A client's websocket frame: final, masked, `payload` with opcode `op` (1 text, 8 close), its
/// header claiming `claimed` bytes (by default the payload's size).
std::string ClientFrame(int op, const std::string& payload, std::uint64_t claimed = ~std::uint64_t{0}) {
  if (claimed == ~std::uint64_t{0}) claimed = payload.size();
  std::string frame(1, static_cast<char>(0x80 | op));
  int length_bytes = 0;
  if (claimed < 126) {
    frame += static_cast<char>(0x80 | claimed);
  } else if (claimed < 65536) {
    frame += static_cast<char>(0x80 | 126);
    length_bytes = 2;
  } else {
    frame += static_cast<char>(0x80 | 127);
    length_bytes = 8;
  }
  for (int b = length_bytes - 1; b >= 0; --b) frame += static_cast<char>((claimed >> (8 * b)) & 0xff);
  const char mask[4] = {0x11, 0x22, 0x33, 0x44};
  frame.append(mask, 4);
  for (std::size_t i = 0; i < payload.size(); ++i) frame += static_cast<char>(payload[i] ^ mask[i % 4]);
  return frame;
}

TEST(FuzzEntries, APageMessageBeyondTheBridgesBoundEndsTheSession) {
  const std::string upgrade =
      "GET /ws HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
  const Entry* entry = FindEntry("websocket_frames");
  const auto run = [&](const std::string& bytes) {
    return entry->run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  };
  EXPECT_TRUE(run(upgrade + ClientFrame(1, std::string(4000, 'x'))).accepted);
  const Outcome big = run(upgrade + ClientFrame(1, std::string(5000, 'x')));
  EXPECT_FALSE(big.accepted);
  EXPECT_NE(big.reason.find("exceeded the locally configured limit"), std::string::npos) << big.reason;
  // A frame that claims 1 GB and sends a few bytes is refused from its header, not held.
  const Outcome claim = run(upgrade + ClientFrame(1, std::string(300, 'x'), std::uint64_t{1} << 30));
  EXPECT_FALSE(claim.accepted);
  EXPECT_NE(claim.reason.find("exceeded the locally configured limit"), std::string::npos) << claim.reason;
  // A request body beyond the bound fails the HTTP read.
  const Outcome body = run("POST / HTTP/1.1\r\nContent-Length: 100000\r\n\r\n" + std::string(100000, 'x'));
  EXPECT_FALSE(body.accepted);
  EXPECT_NE(body.reason.find("HTTP request"), std::string::npos) << body.reason;
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
