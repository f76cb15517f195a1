#include "rbcp/transport/message_parts.h"

#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <utility>

#include "rbcp/core/error.h"
#include "rbcp/transport/random_id.h"
#include "rbcp/transport/wire_check.h"
#include "rbcp_msgs/message_part_t.hpp"

namespace rbcp::transport {
namespace {

std::string Megabytes(std::size_t bytes) {
  const double mb = static_cast<double>(bytes) / (1024.0 * 1024.0);
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MB", mb);
  return text;
}

/// The utime of an encoded rbcp_msgs message: its first field, after the 8-byte fingerprint.
int64_t EncodedUtime(const uint8_t* data, std::size_t size) {
  if (size < 16) return 0;
  uint64_t v = 0;
  for (std::size_t i = 8; i < 16; ++i) v = (v << 8) | data[i];
  int64_t out;
  std::memcpy(&out, &v, sizeof out);
  return out;
}

/// After a whole message of at least this many bytes, the heap's free pages go back to the system.
constexpr std::size_t kTrimAfterBytes = std::size_t{4} << 20;

/// Bytes of every part but the last, for a message of `total` bytes in `count` parts.
int64_t Stride(int64_t total, int64_t count) { return (total + count - 1) / count; }

/// Bytes of part `index` of a message of `total` bytes in parts of `stride` bytes.
int64_t PartBytes(int64_t total, int64_t stride, int64_t index) {
  const int64_t begin = index * stride;
  return std::min(total, begin + stride) - begin;
}

/// Why a part's own fields (the whole message's size and part count, its index and length) cannot
/// describe a part of a message of at most max_message_bytes, or nullopt when they can.
std::optional<std::string> LayoutProblem(const rbcp_msgs::message_part_t& part, std::size_t max_message_bytes) {
  const int64_t total = part.total_size;
  const int64_t count = part.part_count;
  if (total < 1 || static_cast<uint64_t>(total) > max_message_bytes) {
    return "the whole message would be " + std::to_string(total) + " bytes, expected 1 to " +
           std::to_string(max_message_bytes) + " (" + Megabytes(max_message_bytes) + ")";
  }
  if (count < 1 || count > total) {
    return "part_count " + std::to_string(count) + ", expected 1 to the message's " + std::to_string(total) + " bytes";
  }
  const int64_t stride = Stride(total, count);
  if ((count - 1) * stride >= total) {
    return std::to_string(count) + " parts of " + std::to_string(stride) + " bytes do not make " + std::to_string(total) +
           " bytes";
  }
  if (part.index < 0 || part.index >= count) {
    return "index " + std::to_string(part.index) + ", expected 0 to " + std::to_string(count - 1);
  }
  const int64_t expected = PartBytes(total, stride, part.index);
  if (part.num_bytes != expected) {
    return "part " + std::to_string(part.index) + " holds " + std::to_string(part.num_bytes) + " bytes, expected " +
           std::to_string(expected);
  }
  return std::nullopt;
}

}  // namespace

std::string PartChannel(const std::string& channel) { return channel + kPartSuffix; }

std::optional<std::string> WholeChannelOf(const std::string& channel) {
  const std::size_t n = std::strlen(kPartSuffix);
  if (channel.size() <= n || channel.compare(channel.size() - n, n, kPartSuffix) != 0) return std::nullopt;
  return channel.substr(0, channel.size() - n);
}

int64_t PartChecksum(const void* data, std::size_t size) {
  const auto* p = static_cast<const uint8_t*>(data);
  uint64_t h = 0xcbf29ce484222325ULL;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  int64_t out;
  std::memcpy(&out, &h, sizeof out);
  return out;
}

void PartOptions::Validate() const {
  const auto fail = [](const std::string& what) { throw InputError("message parts: " + what); };
  if (part_bytes == 0) fail("part_bytes expected > 0");
  if (max_message_bytes == 0 || max_message_bytes > kMaxPartedMessageBytes) {
    fail("max_message_bytes expected in (0, " + std::to_string(kMaxPartedMessageBytes) + "], got " +
         std::to_string(max_message_bytes));
  }
  if (!(pause_s >= 0.0) || pause_s > 1.0) fail("pause_s expected in [0, 1] s, got " + std::to_string(pause_s));
}

MessagePublisher::MessagePublisher(lcm::LCM& lcm, PartOptions options) : lcm_(lcm), options_(options) {
  options_.Validate();
  if (options_.sender == 0) options_.sender = RandomId();
}

std::string MessagePublisher::TooLarge(const std::string& channel, long long size) const {
  return channel + ": the message is " + std::to_string(size) + " bytes (" + Megabytes(static_cast<std::size_t>(std::max(0LL, size))) +
         "), above the bound of " + std::to_string(options_.max_message_bytes) + " bytes (" +
         Megabytes(options_.max_message_bytes) + ") of a message sent in parts: not sent";
}

std::string MessagePublisher::PublishEncoded(const std::string& channel, const void* data, std::size_t size) {
  if (size <= options_.threshold_bytes) {
    return lcm_.publish(channel, data, static_cast<unsigned>(size)) == 0 ? ""
                                                                          : "LCM could not send the " + channel + " message";
  }
  if (size > options_.max_message_bytes) return TooLarge(channel, static_cast<long long>(size));
  const auto* bytes = static_cast<const uint8_t*>(data);
  const auto total = static_cast<int64_t>(size);
  const int64_t count = (total + static_cast<int64_t>(options_.part_bytes) - 1) / static_cast<int64_t>(options_.part_bytes);
  const int64_t stride = Stride(total, count);
  rbcp_msgs::message_part_t part{};
  part.utime = EncodedUtime(bytes, size);
  part.sender = options_.sender;
  part.sequence = ++sequence_;
  part.checksum = PartChecksum(bytes, size);
  part.total_size = static_cast<int32_t>(total);
  part.part_count = static_cast<int32_t>(count);
  const std::string part_channel = PartChannel(channel);
  ++parted_messages_;
  for (int64_t i = 0; i < count; ++i) {
    if (i > 0 && options_.pause_s > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(options_.pause_s));
    const int64_t begin = i * stride;
    const int64_t end = std::min(total, begin + stride);
    part.index = static_cast<int32_t>(i);
    part.num_bytes = static_cast<int32_t>(end - begin);
    part.bytes.assign(bytes + begin, bytes + end);
    if (lcm_.publish(part_channel, &part) != 0) {
      return "LCM could not send part " + std::to_string(i + 1) + " of " + std::to_string(count) + " of the " + channel +
             " message";
    }
    ++parts_sent_;
  }
  return "";
}

namespace {
/// Bytes held by the incomplete messages of every PartAssembler of the process.
std::atomic<std::size_t> g_buffered_part_bytes{0};
}  // namespace

std::size_t PartAssembler::ProcessBufferedBytes() { return g_buffered_part_bytes.load(); }

PartAssembler::PartAssembler(std::string channel, std::size_t max_message_bytes)
    : channel_(std::move(channel)), max_message_bytes_(std::min(max_message_bytes, kMaxPartedMessageBytes)) {}

PartAssembler::~PartAssembler() { g_buffered_part_bytes -= buffered_; }

PartAssembler::PartAssembler(PartAssembler&& other) noexcept
    : channel_(std::move(other.channel_)),
      max_message_bytes_(other.max_message_bytes_),
      senders_(std::move(other.senders_)),
      buffered_(std::exchange(other.buffered_, 0)),
      completed_(other.completed_),
      abandoned_(other.abandoned_),
      ignored_(other.ignored_) {}

void PartAssembler::Drop(Sender& sender) {
  if (!sender.current) return;
  buffered_ -= sender.current->bytes;
  g_buffered_part_bytes -= sender.current->bytes;
  sender.current.reset();
  ++abandoned_;
}

void PartAssembler::Expire(Clock::time_point now) {
  const auto timeout = std::chrono::duration<double>(kPartTimeout_s);
  for (auto& [id, sender] : senders_) {
    if (sender.current && now - sender.last_heard > timeout) Drop(sender);
  }
}

PartAssembler::Sender& PartAssembler::SenderOf(int64_t id, Clock::time_point now) {
  auto it = senders_.find(id);
  if (it == senders_.end()) {
    if (senders_.size() >= kMaxSenders) {  // the sender heard least recently makes room
      auto oldest = std::min_element(senders_.begin(), senders_.end(), [](const auto& a, const auto& b) {
        return a.second.last_heard < b.second.last_heard;
      });
      Drop(oldest->second);
      senders_.erase(oldest);
    }
    it = senders_.emplace(id, Sender{}).first;
  }
  it->second.last_heard = now;
  return it->second;
}

bool PartAssembler::OfLastMessages(const Sender& sender, int64_t sequence) {
  // The distance is taken in unsigned arithmetic: any two int64 sequences have one.
  return sender.any && sequence <= sender.last_sequence &&
         static_cast<uint64_t>(sender.last_sequence) - static_cast<uint64_t>(sequence) <
             static_cast<uint64_t>(kSequenceWindow);
}

void PartAssembler::StartMessage(Sender& sender, const rbcp_msgs::message_part_t& part) {
  Drop(sender);
  sender.current = Assembly{};
  sender.current->sequence = part.sequence;
  sender.current->checksum = part.checksum;
  sender.current->total = part.total_size;
  sender.current->part_count = part.part_count;
  sender.any = true;
  sender.last_sequence = part.sequence;
}

std::vector<uint8_t> PartAssembler::TakeWhole(Sender& sender) {
  const Assembly& a = *sender.current;
  const int64_t stride = Stride(a.total, a.part_count);
  std::vector<uint8_t> whole(static_cast<std::size_t>(a.total));
  for (const auto& [index, piece] : a.parts) {
    if (!piece.empty()) std::memcpy(whole.data() + static_cast<int64_t>(index) * stride, piece.data(), piece.size());
  }
  buffered_ -= a.bytes;
  g_buffered_part_bytes -= a.bytes;
  sender.current.reset();
  return whole;
}

std::optional<std::vector<uint8_t>> PartAssembler::Add(const void* data, std::size_t size, std::string& problem) {
  problem.clear();
  const std::string where = "a part of " + channel_ + " on " + PartChannel(channel_) + " (" + std::to_string(size) + " bytes)";
  rbcp_msgs::message_part_t part;
  if (auto undecodable = DecodeMessage(data, size, part)) {
    problem = "cannot decode " + where + ": " + *undecodable;
    return std::nullopt;
  }
  const auto fail = [&](const std::string& why) -> std::optional<std::vector<uint8_t>> {
    problem = "rejected " + where + ": " + why;
    return std::nullopt;
  };
  if (const std::optional<std::string> layout = LayoutProblem(part, max_message_bytes_)) return fail(*layout);

  // The part's sender and message: a part of a newer message starts it, one of the last few is late.
  const Clock::time_point now = Clock::now();
  Expire(now);
  Sender& sender = SenderOf(part.sender, now);
  if (!(sender.current && sender.current->sequence == part.sequence)) {
    if (OfLastMessages(sender, part.sequence)) {
      ++ignored_;
      return std::nullopt;
    }
    StartMessage(sender, part);
  }
  Assembly& a = *sender.current;
  if (a.total != part.total_size || a.part_count != part.part_count || a.checksum != part.checksum) {
    Drop(sender);
    return fail("it disagrees with the earlier parts of message " + std::to_string(part.sequence) +
                " (size, part count or checksum): the message is dropped");
  }
  if (a.parts.count(part.index) > 0) {
    ++ignored_;  // a repeat
    return std::nullopt;
  }

  // Kept within the process's bound; the whole message once every part is in.
  const auto bytes = static_cast<std::size_t>(part.num_bytes);
  if (g_buffered_part_bytes.load() + bytes > kMaxBufferedPartBytes) {
    Drop(sender);
    return fail("the incomplete messages in parts of this process would hold more than " +
                Megabytes(kMaxBufferedPartBytes) + ": the message is dropped");
  }
  a.bytes += bytes;
  buffered_ += bytes;
  g_buffered_part_bytes += bytes;
  a.parts.emplace(part.index, std::move(part.bytes));
  if (static_cast<int64_t>(a.parts.size()) < a.part_count) return std::nullopt;
  const int64_t checksum = a.checksum;
  std::vector<uint8_t> whole = TakeWhole(sender);
  if (PartChecksum(whole.data(), whole.size()) != checksum) {
    ++abandoned_;
    return fail("the " + std::to_string(part.part_count) + " parts of message " + std::to_string(part.sequence) +
                " do not match its checksum: the message is dropped");
  }
  ++completed_;
  return whole;
}

ChannelReceiver::ChannelReceiver(lcm::LCM& lcm, const std::string& channel, Deliver deliver, Reject reject)
    : lcm_(lcm),
      channel_(channel),
      deliver_(std::move(deliver)),
      reject_(std::move(reject)),
      whole_faults_(channel, ProcessMessageFaults()),
      part_faults_(PartChannel(channel), ProcessMessageFaults()),
      assembler_(channel) {
  whole_subscription_ = lcm.subscribe(channel, &ChannelReceiver::OnWhole, this);
  part_subscription_ = lcm.subscribe(PartChannel(channel), &ChannelReceiver::OnPart, this);
}

ChannelReceiver::~ChannelReceiver() {
  if (whole_subscription_) lcm_.unsubscribe(whole_subscription_);
  if (part_subscription_) lcm_.unsubscribe(part_subscription_);
}

void ChannelReceiver::OnWhole(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  whole_faults_.Receive(rbuf->data, rbuf->data_size, deliver_);
}

void ChannelReceiver::OnPart(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  part_faults_.Receive(rbuf->data, rbuf->data_size, [this](const void* data, std::size_t size) {
    std::string problem;
    auto whole = assembler_.Add(data, size, problem);
    if (!problem.empty()) {
      if (reject_) reject_(problem);
      return;
    }
    if (!whole) return;
    deliver_(whole->data(), whole->size());
    // A large message leaves freed pages in the heap that glibc keeps by default: give them back.
    const std::size_t large = whole->size();
    whole->clear();
    whole->shrink_to_fit();
    if (large >= kTrimAfterBytes) ::malloc_trim(0);
  });
}

std::string PartJoiner::Add(const std::string& channel, const void* data, std::size_t size, const Whole& whole) {
  const auto base = WholeChannelOf(channel);
  if (!base) {
    whole(channel, data, size);
    return "";
  }
  auto it = assemblers_.find(*base);
  if (it == assemblers_.end()) it = assemblers_.emplace(*base, PartAssembler(*base, max_message_bytes_)).first;
  std::string problem;
  const auto bytes = it->second.Add(data, size, problem);
  if (bytes) whole(*base, bytes->data(), bytes->size());
  return problem;
}

long PartJoiner::abandoned() const {
  long n = 0;
  for (const auto& [channel, assembler] : assemblers_) n += assembler.abandoned();
  return n;
}

}  // namespace rbcp::transport
