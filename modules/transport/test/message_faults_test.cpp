#include "rbcp/transport/message_faults.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rbcp/core/error.h"

namespace rbcp::transport {
namespace {

std::string ErrorOf(const std::string& spec) {
  try {
    ParseMessageFaults(spec);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MessageFaults, ReadsTheRatesStrictly) {
  const MessageFaultRates r = ParseMessageFaults("drop=0.1,duplicate=0.05,reorder=0.2,seed=7");
  EXPECT_DOUBLE_EQ(r.drop, 0.1);
  EXPECT_DOUBLE_EQ(r.duplicate, 0.05);
  EXPECT_DOUBLE_EQ(r.reorder, 0.2);
  EXPECT_EQ(r.seed, 7u);
  EXPECT_FALSE(ParseMessageFaults("").Any());
  EXPECT_EQ(ErrorOf("drop"), "RBCP_MESSAGE_FAULTS 'drop': expected key=value, got 'drop'");
  EXPECT_EQ(ErrorOf("lose=0.1"),
            "RBCP_MESSAGE_FAULTS 'lose=0.1': unknown key 'lose' (keys: drop, duplicate, reorder, seed)");
  EXPECT_EQ(ErrorOf("drop=1"), "RBCP_MESSAGE_FAULTS 'drop=1': 'drop' expected a probability in [0, 1), got '1'");
  EXPECT_EQ(ErrorOf("reorder=nan"),
            "RBCP_MESSAGE_FAULTS 'reorder=nan': 'reorder' expected a probability in [0, 1), got 'nan'");
  EXPECT_EQ(ErrorOf("drop=0.1x"),
            "RBCP_MESSAGE_FAULTS 'drop=0.1x': 'drop' expected a probability in [0, 1), got '0.1x'");
  EXPECT_EQ(ErrorOf("seed=-3"), "RBCP_MESSAGE_FAULTS 'seed=-3': 'seed' expected a non-negative integer, got '-3'");
  EXPECT_EQ(ErrorOf("drop=0.5,duplicate=0.5"),
            "RBCP_MESSAGE_FAULTS 'drop=0.5,duplicate=0.5': drop + duplicate + reorder expected below 1");
}

/// Sends messages 0..n-1 (one byte each) through `faults` and returns what was delivered, in order.
std::vector<int> Through(ReceiveFaults& faults, int n) {
  std::vector<int> out;
  for (int i = 0; i < n; ++i) {
    const unsigned char byte = static_cast<unsigned char>(i);
    faults.Receive(&byte, 1, [&](const void* data, std::size_t size) {
      ASSERT_EQ(size, 1u);
      out.push_back(*static_cast<const unsigned char*>(data));
    });
  }
  return out;
}

TEST(MessageFaults, WithoutRatesEveryMessageGoesThroughInOrder) {
  ReceiveFaults faults("CHANNEL", std::nullopt);
  const std::vector<int> out = Through(faults, 50);
  ASSERT_EQ(out.size(), 50u);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(out[i], i);
}

TEST(MessageFaults, DropsDuplicatesAndReordersAtTheirRatesTheSameWayForTheSameSeed) {
  MessageFaultRates rates;
  rates.drop = 0.1;
  rates.duplicate = 0.1;
  rates.reorder = 0.1;
  rates.seed = 3;
  ReceiveFaults faults("ROBOT_STATE", rates);
  const std::vector<int> out = Through(faults, 200);
  // Each fault happened, at about its rate.
  EXPECT_GT(faults.dropped(), 5);
  EXPECT_LT(faults.dropped(), 40);
  EXPECT_GT(faults.duplicated(), 5);
  EXPECT_LT(faults.duplicated(), 40);
  EXPECT_GT(faults.reordered(), 5);
  EXPECT_LT(faults.reordered(), 40);
  // A message delivered is one that was sent; duplicates come back to back, a reordered message
  // right after a newer one.
  int back_to_back = 0, late = 0;
  for (std::size_t i = 1; i < out.size(); ++i) {
    if (out[i] == out[i - 1]) ++back_to_back;
    if (out[i] < out[i - 1]) ++late;
  }
  EXPECT_EQ(back_to_back, faults.duplicated());
  EXPECT_GT(late, 0);
  // The same seed and channel give the same faults; another channel others.
  ReceiveFaults again("ROBOT_STATE", rates);
  EXPECT_EQ(Through(again, 200), out);
  ReceiveFaults other("CONTACT_PLAN", rates);
  EXPECT_NE(Through(other, 200), out);
}

}  // namespace
}  // namespace rbcp::transport
