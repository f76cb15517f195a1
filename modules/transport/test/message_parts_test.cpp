#include "rbcp/transport/message_parts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/wire_check.h"
#include "rbcp_msgs/message_part_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace rbcp::transport {
namespace {

using Bytes = std::vector<uint8_t>;

/// A terrain of `n` triangles (a strip), `n` + 2 vertices; its encoding is about 36 n bytes.
rbcp_msgs::terrain_mesh_t Terrain(int n, int64_t utime) {
  rbcp_msgs::terrain_mesh_t msg{};
  msg.utime = utime;
  msg.scenario_name = "strip";
  msg.num_vertices = n + 2;
  for (int v = 0; v < n + 2; ++v) msg.vertices.push_back({0.01 * (v / 2), 0.01 * (v % 2), 1e-3 * v + 1e-6 * utime});
  msg.num_triangles = n;
  for (int t = 0; t < n; ++t) msg.triangles.push_back({t, t + 1, t + 2});
  return msg;
}

template <typename Msg>
Bytes Encode(const Msg& msg) {
  Bytes buf(static_cast<std::size_t>(msg.getEncodedSize()));
  EXPECT_EQ(msg.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return buf;
}

void Drain(lcm::LCM& lcm) {
  while (lcm.handleTimeout(0) > 0) {
  }
}

/// Every raw message of one channel, as published.
class Tap {
 public:
  Tap(lcm::LCM& lcm, const std::string& channel) : lcm_(lcm) {
    subscription_ = lcm.subscribe(channel, &Tap::On, this);
  }
  ~Tap() { lcm_.unsubscribe(subscription_); }
  std::vector<Bytes> messages;

 private:
  void On(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    const auto* p = static_cast<const uint8_t*>(rbuf->data);
    messages.emplace_back(p, p + rbuf->data_size);
  }
  lcm::LCM& lcm_;
  lcm::Subscription* subscription_;
};

PartOptions SmallParts() {
  PartOptions o;
  o.threshold_bytes = 1000;
  o.part_bytes = 300;
  o.pause_s = 0.0;
  o.sender = 7;
  return o;
}

/// The encoded parts of `msg` as `options` cut them.
template <typename Msg>
std::vector<Bytes> PartsOf(const Msg& msg, PartOptions options) {
  lcm::LCM lcm("memq://");
  Tap tap(lcm, "T/PART");
  MessagePublisher publisher(lcm, options);
  EXPECT_EQ(publisher.Publish("T", msg), "");
  Drain(lcm);
  return tap.messages;
}

rbcp_msgs::message_part_t DecodePart(const Bytes& b) {
  rbcp_msgs::message_part_t part;
  EXPECT_FALSE(DecodeMessage(b.data(), b.size(), part).has_value());
  return part;
}

TEST(MessageParts, ChannelNames) {
  EXPECT_EQ(PartChannel("TERRAIN"), "TERRAIN/PART");
  EXPECT_EQ(WholeChannelOf("TERRAIN/PART").value_or("none"), "TERRAIN");
  EXPECT_FALSE(WholeChannelOf("TERRAIN").has_value());
  EXPECT_FALSE(WholeChannelOf("/PART").has_value());
}

TEST(MessageParts, ASmallMessageGoesWholeOnItsChannel) {
  lcm::LCM lcm("memq://");
  Tap whole(lcm, "T");
  Tap parts(lcm, "T/PART");
  MessagePublisher publisher(lcm, SmallParts());
  const auto msg = Terrain(10, 5);
  ASSERT_LT(msg.getEncodedSize(), 1000);
  EXPECT_EQ(publisher.Publish("T", msg), "");
  Drain(lcm);
  ASSERT_EQ(whole.messages.size(), 1u);
  EXPECT_EQ(whole.messages[0], Encode(msg)) << "the same bytes as lcm.publish sends";
  EXPECT_TRUE(parts.messages.empty());
  EXPECT_EQ(publisher.parted_messages(), 0);
}

TEST(MessageParts, ALargeMessageGoesInPartsAndComesBackWhole) {
  lcm::LCM lcm("memq://");
  Tap whole(lcm, "T");
  Tap parts(lcm, "T/PART");
  LatestMessage<rbcp_msgs::terrain_mesh_t> latest(lcm, "T");
  MessagePublisher publisher(lcm, SmallParts());
  const auto msg = Terrain(100, 42);
  const Bytes encoded = Encode(msg);
  EXPECT_EQ(publisher.Publish("T", msg), "");
  Drain(lcm);
  EXPECT_TRUE(whole.messages.empty()) << "nothing on the channel itself";
  const std::size_t count = (encoded.size() + 299) / 300;
  ASSERT_EQ(parts.messages.size(), count);
  for (std::size_t i = 0; i < count; ++i) {
    const auto part = DecodePart(parts.messages[i]);
    EXPECT_EQ(part.index, static_cast<int32_t>(i));
    EXPECT_EQ(part.part_count, static_cast<int32_t>(count));
    EXPECT_EQ(part.total_size, static_cast<int32_t>(encoded.size()));
    EXPECT_EQ(part.utime, 42);
    EXPECT_EQ(part.sender, 7);
    EXPECT_EQ(part.sequence, 1);
    EXPECT_EQ(part.checksum, PartChecksum(encoded.data(), encoded.size()));
  }
  const auto got = latest.Take();
  ASSERT_TRUE(got.has_value()) << latest.TakeDecodeError().value_or("");
  EXPECT_EQ(Encode(*got), encoded);
  EXPECT_EQ(latest.received(), 1);
}

TEST(MessageParts, PartsInAnyOrderMakeTheSameMessage) {
  const auto msg = Terrain(100, 1);
  const Bytes encoded = Encode(msg);
  std::vector<Bytes> parts = PartsOf(msg, SmallParts());
  ASSERT_GT(parts.size(), 5u);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 5; ++trial) {
    std::shuffle(parts.begin(), parts.end(), rng);
    PartAssembler assembler("T");
    std::optional<Bytes> whole;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      std::string problem;
      auto out = assembler.Add(parts[i].data(), parts[i].size(), problem);
      EXPECT_EQ(problem, "");
      EXPECT_EQ(out.has_value(), i + 1 == parts.size()) << "whole only with the last part in";
      if (out) whole = std::move(out);
    }
    ASSERT_TRUE(whole.has_value());
    EXPECT_EQ(*whole, encoded);
  }
}

TEST(MessageParts, ALostPartLosesTheMessageAndTheNextOneComes) {
  lcm::LCM lcm("memq://");
  PartOptions options = SmallParts();
  MessagePublisher publisher(lcm, options);
  Tap parts(lcm, "T/PART");
  ASSERT_EQ(publisher.Publish("T", Terrain(100, 1)), "");
  ASSERT_EQ(publisher.Publish("T", Terrain(100, 2)), "");
  Drain(lcm);
  const std::size_t per_message = parts.messages.size() / 2;
  PartAssembler assembler("T");
  std::vector<Bytes> wholes;
  for (std::size_t i = 0; i < parts.messages.size(); ++i) {
    if (i == 3) continue;  // lost
    std::string problem;
    auto out = assembler.Add(parts.messages[i].data(), parts.messages[i].size(), problem);
    EXPECT_EQ(problem, "");
    if (out) wholes.push_back(*out);
  }
  ASSERT_EQ(wholes.size(), 1u);
  EXPECT_EQ(wholes[0], Encode(Terrain(100, 2)));
  EXPECT_EQ(assembler.abandoned(), 1) << "the first message, dropped when the second started";
  EXPECT_EQ(assembler.buffered_bytes(), 0u);
  EXPECT_GT(per_message, 3u);
}

TEST(MessageParts, RepeatedAndLatePartsAreIgnored) {
  lcm::LCM lcm("memq://");
  MessagePublisher publisher(lcm, SmallParts());
  Tap parts(lcm, "T/PART");
  ASSERT_EQ(publisher.Publish("T", Terrain(100, 1)), "");
  const std::size_t first = [&] {
    Drain(lcm);
    return parts.messages.size();
  }();
  ASSERT_EQ(publisher.Publish("T", Terrain(100, 2)), "");
  Drain(lcm);
  PartAssembler assembler("T");
  std::vector<Bytes> wholes;
  const auto add = [&](const Bytes& b) {
    std::string problem;
    auto out = assembler.Add(b.data(), b.size(), problem);
    EXPECT_EQ(problem, "");
    if (out) wholes.push_back(*out);
  };
  // The second message's parts, each twice, with a part of the first (older) message in between.
  for (std::size_t i = first; i < parts.messages.size(); ++i) {
    add(parts.messages[i]);
    add(parts.messages[i]);
    if (i == first + 1) add(parts.messages[0]);
  }
  // Its parts again after it was whole: no second copy.
  for (std::size_t i = first; i < parts.messages.size(); ++i) add(parts.messages[i]);
  ASSERT_EQ(wholes.size(), 1u);
  EXPECT_EQ(wholes[0], Encode(Terrain(100, 2)));
  EXPECT_EQ(assembler.completed(), 1);
  EXPECT_GE(assembler.ignored(), static_cast<long>(2 * (parts.messages.size() - first)));
}

TEST(MessageParts, AnotherSendersPartsLeaveAnIncompleteMessageAlone) {
  const auto a = PartsOf(Terrain(100, 1), SmallParts());
  PartOptions other = SmallParts();
  other.sender = 8;
  const auto b = PartsOf(Terrain(100, 2), other);
  ASSERT_GT(a.size(), 3u);
  PartAssembler assembler("T");
  std::string problem;
  EXPECT_FALSE(assembler.Add(a[0].data(), a[0].size(), problem));
  std::vector<Bytes> wholes;
  // The other sender's message goes through whole, its parts interleaved with the first's.
  for (std::size_t i = 0; i < std::max(a.size(), b.size()); ++i) {
    if (i < b.size()) {
      auto out = assembler.Add(b[i].data(), b[i].size(), problem);
      EXPECT_EQ(problem, "");
      if (out) wholes.push_back(*out);
    }
    if (i + 1 < a.size()) {
      auto out = assembler.Add(a[i + 1].data(), a[i + 1].size(), problem);
      EXPECT_EQ(problem, "");
      if (out) wholes.push_back(*out);
    }
  }
  ASSERT_EQ(wholes.size(), 2u);
  EXPECT_TRUE(std::find(wholes.begin(), wholes.end(), Encode(Terrain(100, 1))) != wholes.end());
  EXPECT_TRUE(std::find(wholes.begin(), wholes.end(), Encode(Terrain(100, 2))) != wholes.end());
  EXPECT_EQ(assembler.abandoned(), 0);
  EXPECT_EQ(assembler.buffered_bytes(), 0u);
}

TEST(MessageParts, APartClaimingAHugeMessageHoldsOnlyItsOwnBytes) {
  rbcp_msgs::message_part_t p{};
  p.sender = 99;
  p.sequence = 1;
  p.total_size = static_cast<int32_t>(kMaxPartedMessageBytes);
  p.part_count = p.total_size;  // parts of one byte
  p.index = 0;
  p.num_bytes = 1;
  p.bytes = {42};
  PartAssembler assembler("T");
  std::string problem;
  for (int channel = 0; channel < 5; ++channel) {
    const Bytes b = Encode(p);
    EXPECT_FALSE(assembler.Add(b.data(), b.size(), problem).has_value());
    EXPECT_EQ(problem, "");
    ++p.sequence;
  }
  EXPECT_EQ(assembler.buffered_bytes(), 1u) << "each newer message of the sender drops the one before";
  EXPECT_LE(PartAssembler::ProcessBufferedBytes(), 1u);
}

TEST(MessageParts, AForgedSequenceDoesNotShutASenderOut) {
  const auto parts = PartsOf(Terrain(100, 1), SmallParts());  // sender 7, message 1
  auto forged = DecodePart(parts[0]);
  forged.sequence = std::numeric_limits<int64_t>::max();
  PartAssembler assembler("T");
  std::string problem;
  const Bytes f = Encode(forged);
  EXPECT_FALSE(assembler.Add(f.data(), f.size(), problem).has_value());
  std::optional<Bytes> whole;
  for (const Bytes& b : parts) {
    if (auto out = assembler.Add(b.data(), b.size(), problem)) whole = out;
  }
  ASSERT_TRUE(whole.has_value()) << "message 1 is far from INT64_MAX: a new message, not a late one";
  EXPECT_EQ(*whole, Encode(Terrain(100, 1)));
}

TEST(MessageParts, TheProcessBoundOnIncompleteMessagesDropsAMessageBeyondIt) {
  // Senders that each start a message and never finish it, until the bound is reached.
  std::vector<PartAssembler> assemblers;
  for (int k = 0; k < 4; ++k) assemblers.emplace_back("T" + std::to_string(k));
  rbcp_msgs::message_part_t p{};
  p.sequence = 1;
  p.total_size = static_cast<int32_t>(kMaxPartedMessageBytes);
  p.part_count = 64;
  p.num_bytes = p.total_size / p.part_count;
  p.bytes.assign(static_cast<std::size_t>(p.num_bytes), 1);
  std::string problem;
  std::string last_problem;
  for (int part = 0; part < 40; ++part) {
    for (std::size_t k = 0; k < assemblers.size(); ++k) {
      p.sender = static_cast<int64_t>(k) + 1;
      p.index = part;
      const Bytes b = Encode(p);
      assemblers[k].Add(b.data(), b.size(), problem);
      if (!problem.empty()) last_problem = problem;
      EXPECT_LE(PartAssembler::ProcessBufferedBytes(), PartAssembler::kMaxBufferedPartBytes);
    }
  }
  EXPECT_NE(last_problem.find("would hold more than 128.0 MB"), std::string::npos) << last_problem;
  long abandoned = 0;
  for (const PartAssembler& a : assemblers) abandoned += a.abandoned();
  EXPECT_GT(abandoned, 0);
  assemblers.clear();
  EXPECT_EQ(PartAssembler::ProcessBufferedBytes(), 0u) << "freed with the assemblers";
}

TEST(MessageParts, PartsThatDoNotFitTogetherAreRejected) {
  auto parts = PartsOf(Terrain(100, 1), SmallParts());
  ASSERT_GT(parts.size(), 3u);
  const auto reencode = [](const rbcp_msgs::message_part_t& p) { return Encode(p); };
  std::string problem;

  {  // A changed byte: the checksum fails once the message is whole.
    PartAssembler assembler("T");
    auto p = DecodePart(parts[1]);
    p.bytes[5] ^= 0x40;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const Bytes b = i == 1 ? reencode(p) : parts[i];
      EXPECT_FALSE(assembler.Add(b.data(), b.size(), problem).has_value());
    }
    EXPECT_NE(problem.find("do not match its checksum"), std::string::npos) << problem;
    EXPECT_EQ(assembler.completed(), 0);
  }
  {  // A part whose size disagrees with its index.
    PartAssembler assembler("T");
    auto p = DecodePart(parts[0]);
    const std::string expected = std::to_string(p.num_bytes);
    p.bytes.pop_back();
    p.num_bytes -= 1;
    const Bytes b = reencode(p);
    EXPECT_FALSE(assembler.Add(b.data(), b.size(), problem).has_value());
    EXPECT_NE(problem.find("part 0 holds " + std::to_string(p.num_bytes) + " bytes, expected " + expected), std::string::npos)
        << problem;
  }
  {  // A part claiming another total size than its siblings: the message is dropped.
    PartAssembler assembler("T");
    EXPECT_FALSE(assembler.Add(parts[0].data(), parts[0].size(), problem).has_value());
    EXPECT_EQ(problem, "");
    auto p = DecodePart(parts[1]);
    p.total_size += 1;
    const Bytes b = reencode(p);
    EXPECT_FALSE(assembler.Add(b.data(), b.size(), problem).has_value());
    EXPECT_NE(problem.find("disagrees with the earlier parts"), std::string::npos) << problem;
    for (std::size_t i = 1; i < parts.size(); ++i) {
      EXPECT_FALSE(assembler.Add(parts[i].data(), parts[i].size(), problem).has_value())
          << "the rest of a dropped message never makes it whole";
    }
  }
  {  // An index out of range, a count that cannot cut the size.
    PartAssembler assembler("T");
    auto p = DecodePart(parts[0]);
    p.index = p.part_count;
    Bytes b = reencode(p);
    EXPECT_FALSE(assembler.Add(b.data(), b.size(), problem).has_value());
    EXPECT_NE(problem.find("index"), std::string::npos) << problem;
    p = DecodePart(parts[0]);
    p.part_count = p.total_size + 1;
    b = reencode(p);
    EXPECT_FALSE(assembler.Add(b.data(), b.size(), problem).has_value());
    EXPECT_NE(problem.find("part_count"), std::string::npos) << problem;
  }
  {  // Not a part at all.
    PartAssembler assembler("T");
    const Bytes garbage = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    EXPECT_FALSE(assembler.Add(garbage.data(), garbage.size(), problem).has_value());
    EXPECT_NE(problem.find("cannot decode a part of T on T/PART"), std::string::npos) << problem;
  }
}

TEST(MessageParts, AMessageAboveTheBoundIsNeitherSentNorTaken) {
  lcm::LCM lcm("memq://");
  Tap whole(lcm, "T");
  Tap parts(lcm, "T/PART");
  PartOptions options = SmallParts();
  options.max_message_bytes = 2000;
  MessagePublisher publisher(lcm, options);
  const auto msg = Terrain(100, 1);
  const std::string size = std::to_string(msg.getEncodedSize());
  const std::string problem = publisher.Publish("T", msg);
  EXPECT_EQ(problem, "T: the message is " + size + " bytes (0.0 MB), above the bound of 2000 bytes (0.0 MB) of a message "
                     "sent in parts: not sent");
  Drain(lcm);
  EXPECT_TRUE(whole.messages.empty());
  EXPECT_TRUE(parts.messages.empty());

  // A receiver bounds what it puts together the same way, before it allocates.
  const auto sent = PartsOf(msg, SmallParts());
  PartAssembler assembler("T", 2000);
  std::string why;
  EXPECT_FALSE(assembler.Add(sent[0].data(), sent[0].size(), why).has_value());
  EXPECT_NE(why.find("the whole message would be " + size + " bytes, expected 1 to 2000"), std::string::npos) << why;
  EXPECT_EQ(assembler.buffered_bytes(), 0u);
}

TEST(MessageParts, ALatestMessageReportsARejectedPart) {
  lcm::LCM lcm("memq://");
  LatestMessage<rbcp_msgs::terrain_mesh_t> latest(lcm, "T");
  const Bytes garbage = {1, 2, 3};
  lcm.publish("T/PART", garbage.data(), static_cast<unsigned>(garbage.size()));
  Drain(lcm);
  const auto error = latest.TakeDecodeError();
  ASSERT_TRUE(error.has_value());
  EXPECT_NE(error->find("cannot decode a part of T on T/PART (3 bytes)"), std::string::npos) << *error;
  EXPECT_FALSE(latest.Take().has_value());
}

TEST(MessageParts, LostDuplicatedAndReorderedPartsNeverMakeACorruptedMessage) {
  lcm::LCM lcm("memq://");
  MessagePublisher publisher(lcm, SmallParts());
  Tap parts(lcm, "T/PART");
  std::set<Bytes> sent;
  for (int i = 1; i <= 60; ++i) {
    const auto msg = Terrain(60 + i, i);
    sent.insert(Encode(msg));
    ASSERT_EQ(publisher.Publish("T", msg), "");
  }
  Drain(lcm);
  MessageFaultRates rates;
  rates.drop = 0.03;
  rates.duplicate = 0.2;
  rates.reorder = 0.2;
  rates.seed = 11;
  ReceiveFaults faults("T/PART", rates);
  PartAssembler assembler("T");
  int wholes = 0;
  for (const Bytes& p : parts.messages) {
    faults.Receive(p.data(), p.size(), [&](const void* data, std::size_t size) {
      std::string problem;
      const auto out = assembler.Add(data, size, problem);
      EXPECT_EQ(problem, "");
      if (!out) return;
      ++wholes;
      EXPECT_EQ(sent.count(*out), 1u) << "every message put together is one that was sent";
    });
  }
  EXPECT_GT(faults.dropped(), 0);
  EXPECT_GT(faults.duplicated(), 0);
  EXPECT_GT(faults.reordered(), 0);
  EXPECT_GT(wholes, 10);
  EXPECT_LT(wholes, 60) << "messages with a lost part are lost";
  EXPECT_LE(wholes + assembler.abandoned(), 60);
}

TEST(MessageParts, AJoinerPassesOrdinaryMessagesAndJoinsParts) {
  const auto msg = Terrain(100, 9);
  const auto parts = PartsOf(msg, SmallParts());
  PartJoiner joiner;
  std::vector<std::pair<std::string, Bytes>> out;
  const auto whole = [&](const std::string& channel, const void* data, std::size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    out.emplace_back(channel, Bytes(p, p + size));
  };
  const Bytes state = {1, 2, 3};
  for (std::size_t i = 0; i < parts.size(); ++i) {
    EXPECT_EQ(joiner.Add("T/PART", parts[i].data(), parts[i].size(), whole), "");
    EXPECT_EQ(joiner.Add("STATE", state.data(), state.size(), whole), "");
  }
  ASSERT_EQ(out.size(), parts.size() + 1);
  EXPECT_EQ(out[parts.size() - 1].first, "T") << "whole at its last part, before the state that followed it";
  EXPECT_EQ(out[parts.size() - 1].second, Encode(msg));
  EXPECT_EQ(out.back().first, "STATE");
}

TEST(MessageParts, ATerrainOfTwoHundredThousandTrianglesWithTheDefaultParts) {
  lcm::LCM lcm("memq://");
  LatestMessage<rbcp_msgs::terrain_mesh_t> latest(lcm, "TERRAIN");
  Tap parts(lcm, "TERRAIN/PART");
  PartOptions options;
  options.pause_s = 0.0;  // memq:// has no socket buffer to overflow
  MessagePublisher publisher(lcm, options);
  const auto msg = Terrain(200000, 3);
  ASSERT_GT(msg.getEncodedSize(), 7000000);
  EXPECT_EQ(publisher.Publish("TERRAIN", msg), "");
  Drain(lcm);
  EXPECT_EQ(parts.messages.size(), static_cast<std::size_t>((msg.getEncodedSize() + (256 << 10) - 1) / (256 << 10)));
  const auto got = latest.Take();
  ASSERT_TRUE(got.has_value()) << latest.TakeDecodeError().value_or("");
  EXPECT_EQ(got->num_triangles, 200000);
  EXPECT_EQ(got->vertices, msg.vertices);
  EXPECT_EQ(got->triangles, msg.triangles);
}

}  // namespace
}  // namespace rbcp::transport
