#pragma once
/// Large messages in parts. LCM's UDP multicast sends a message as one burst of 64 kB datagrams,
/// and a burst of several megabytes overflows the receivers' socket buffers (the kernel caps
/// them at net.core.rmem_max): such a message is lost without a word. A MessagePublisher sends a
/// message above its threshold (1 MB) as numbered parts (rbcp_msgs::message_part_t) on the
/// companion channel CHANNEL/PART, with a short pause between parts so that the receivers keep
/// up; smaller messages go on CHANNEL as before. Every subscription of the transport
/// (LatestMessage, EveryMessage, through a ChannelReceiver) puts the parts back together with
/// strict checks and decodes the whole message as if it had come on CHANNEL; the log readers do
/// the same with a PartJoiner. A part lost means the message is lost (as a lost datagram does):
/// the next repeat of the channel brings it again.

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/transport/message_faults.h"

namespace rbcp_msgs {
class message_part_t;
}  // namespace rbcp_msgs

namespace rbcp::transport {

/// The companion channel of CHANNEL that carries its messages in parts: CHANNEL + kPartSuffix.
inline constexpr const char* kPartSuffix = "/PART";
/// The largest message sent or put back together in parts [bytes] (64 MB).
inline constexpr std::size_t kMaxPartedMessageBytes = std::size_t{64} << 20;

std::string PartChannel(const std::string& channel);
/// CHANNEL when `channel` is CHANNEL/PART, otherwise nullopt.
std::optional<std::string> WholeChannelOf(const std::string& channel);

/// 64-bit FNV-1a of `size` bytes: the checksum of a message in parts.
int64_t PartChecksum(const void* data, std::size_t size);

struct PartOptions {
  std::size_t threshold_bytes = std::size_t{1} << 20;  ///< messages above this many bytes go in parts
  std::size_t part_bytes = std::size_t{256} << 10;     ///< the most bytes of one part (parts are cut equal)
  double pause_s = 0.002;                              ///< wall-clock pause between two parts [s]
  std::size_t max_message_bytes = kMaxPartedMessageBytes;  ///< larger messages are not sent
  int64_t sender = 0;  ///< the sender named in the parts; 0: drawn at random when the publisher is made
  /// Throws InputError naming what is wrong (a part size of 0, a bound above
  /// kMaxPartedMessageBytes, a pause outside [0, 1] s).
  void Validate() const;
};

/// Publishes messages whole or, above the threshold, in parts on CHANNEL/PART. Not thread-safe:
/// one publisher per thread.
class MessagePublisher {
 public:
  explicit MessagePublisher(lcm::LCM& lcm, PartOptions options = {});

  /// Sends `msg` on `channel`: as an ordinary LCM message up to the threshold, in parts above it.
  /// Returns "" when sent, otherwise why nothing (or not every part) was sent: a message above
  /// max_message_bytes is not sent, and the reason names its size and the bound.
  template <typename Msg>
  std::string Publish(const std::string& channel, const Msg& msg) {
    const int size = msg.getEncodedSize();
    if (size >= 0 && static_cast<std::size_t>(size) <= options_.threshold_bytes) {
      return lcm_.publish(channel, &msg) == 0 ? "" : "LCM could not send the " + channel + " message";
    }
    if (size < 0 || static_cast<std::size_t>(size) > options_.max_message_bytes) return TooLarge(channel, size);
    buffer_.resize(static_cast<std::size_t>(size));
    if (msg.encode(buffer_.data(), 0, size) != size) return "cannot encode the " + channel + " message";
    return PublishEncoded(channel, buffer_.data(), buffer_.size());
  }

  /// Sends an encoded message of the rbcp_msgs package (its utime is its first field) the same way.
  std::string PublishEncoded(const std::string& channel, const void* data, std::size_t size);

  const PartOptions& options() const { return options_; }
  /// Messages sent in parts so far, and their parts.
  long parted_messages() const { return parted_messages_; }
  long parts_sent() const { return parts_sent_; }

 private:
  std::string TooLarge(const std::string& channel, long long size) const;

  lcm::LCM& lcm_;
  PartOptions options_;
  int64_t sequence_ = 0;
  std::vector<uint8_t> buffer_;
  long parted_messages_ = 0;
  long parts_sent_ = 0;
};

/// Puts the parts of one channel's messages back together, one message at a time per sender: a
/// part of a sender's newer message (a higher sequence) drops that sender's incomplete one; a
/// repeat of a part already in, or a part of one of the sender's last kSequenceWindow messages,
/// is ignored; another sender's parts (a foreign or forged part interleaved) leave it alone.
/// Before a part is kept its own fields are checked (sizes, index, the bound) and against the
/// message's other parts (the same size, count and checksum); the whole message is handed out
/// only when every part is in and its checksum matches. Memory follows the bytes received, not
/// the size a part claims: the parts of incomplete messages of the whole process hold at most
/// kMaxBufferedPartBytes (a part beyond drops its message), an incomplete message without a new
/// part for kPartTimeout_s is dropped, and at most kMaxSenders senders are followed per channel
/// (the one heard least recently makes room).
class PartAssembler {
 public:
  static constexpr std::size_t kMaxBufferedPartBytes = std::size_t{128} << 20;
  static constexpr double kPartTimeout_s = 10.0;
  static constexpr std::size_t kMaxSenders = 8;
  static constexpr int64_t kSequenceWindow = 64;

  explicit PartAssembler(std::string channel, std::size_t max_message_bytes = kMaxPartedMessageBytes);
  ~PartAssembler();
  PartAssembler(PartAssembler&& other) noexcept;
  PartAssembler& operator=(PartAssembler&&) = delete;
  PartAssembler(const PartAssembler&) = delete;
  PartAssembler& operator=(const PartAssembler&) = delete;

  /// Takes one encoded message_part_t. Returns the whole message's bytes when this part completes
  /// it. A part that cannot belong to a whole message sets `problem` (naming the channel) and is
  /// dropped, with the incomplete message it claims to belong to.
  std::optional<std::vector<uint8_t>> Add(const void* data, std::size_t size, std::string& problem);

  long completed() const { return completed_; }
  /// Incomplete messages dropped (a part was lost, a newer message started, it timed out, or
  /// the memory bound was reached).
  long abandoned() const { return abandoned_; }
  /// Parts ignored: repeats of parts already in, parts of older or finished messages.
  long ignored() const { return ignored_; }
  /// Bytes held for this channel's incomplete messages.
  std::size_t buffered_bytes() const { return buffered_; }
  /// Bytes held for the incomplete messages of every assembler of the process.
  static std::size_t ProcessBufferedBytes();

 private:
  using Clock = std::chrono::steady_clock;
  struct Assembly {
    int64_t sequence = 0;
    int64_t checksum = 0;
    int64_t total = 0;
    int32_t part_count = 0;
    std::map<int32_t, std::vector<uint8_t>> parts;  ///< by index: only what was received
    std::size_t bytes = 0;
  };
  struct Sender {
    std::optional<Assembly> current;
    bool any = false;  ///< a message was started: last_sequence holds
    int64_t last_sequence = 0;
    Clock::time_point last_heard;
  };
  /// Drops the sender's incomplete message (counted abandoned) and frees its bytes.
  void Drop(Sender& sender);
  /// Drops incomplete messages without a part for kPartTimeout_s.
  void Expire(Clock::time_point now);
  /// The sender with this id, heard now (a new one may drop the sender heard least recently).
  Sender& SenderOf(int64_t id, Clock::time_point now);
  /// The sequence is one of the sender's last kSequenceWindow messages (a late part).
  static bool OfLastMessages(const Sender& sender, int64_t sequence);
  /// Drops the sender's incomplete message and starts the one `part` belongs to.
  void StartMessage(Sender& sender, const rbcp_msgs::message_part_t& part);
  /// The sender's message, every part in, put together; its bytes are freed.
  std::vector<uint8_t> TakeWhole(Sender& sender);

  std::string channel_;
  std::size_t max_message_bytes_;
  std::map<int64_t, Sender> senders_;
  std::size_t buffered_ = 0;
  long completed_ = 0;
  long abandoned_ = 0;
  long ignored_ = 0;
};

/// The messages of a channel as its subscribers see them: subscribes to CHANNEL and CHANNEL/PART,
/// each through the process's message faults (message_faults.h), and hands every whole encoded
/// message to `deliver`, ordinary or put back together from its parts. A part that cannot belong
/// to a whole message goes to `reject` with the reason.
class ChannelReceiver {
 public:
  using Deliver = std::function<void(const void* data, std::size_t size)>;
  using Reject = std::function<void(const std::string& problem)>;
  ChannelReceiver(lcm::LCM& lcm, const std::string& channel, Deliver deliver, Reject reject);
  ~ChannelReceiver();
  ChannelReceiver(const ChannelReceiver&) = delete;
  ChannelReceiver& operator=(const ChannelReceiver&) = delete;

  const std::string& channel() const { return channel_; }
  const PartAssembler& assembler() const { return assembler_; }

 private:
  void OnWhole(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void OnPart(const lcm::ReceiveBuffer* rbuf, const std::string& channel);

  lcm::LCM& lcm_;
  std::string channel_;
  Deliver deliver_;
  Reject reject_;
  ReceiveFaults whole_faults_;
  ReceiveFaults part_faults_;
  PartAssembler assembler_;
  lcm::Subscription* whole_subscription_ = nullptr;
  lcm::Subscription* part_subscription_ = nullptr;
};

/// The same for a sequence of messages of many channels, such as an LCM log or a subscription to
/// every channel: an ordinary message goes to `whole` as it is; a part (on CHANNEL/PART) is kept
/// until it completes its message, which then goes to `whole` under CHANNEL.
class PartJoiner {
 public:
  using Whole = std::function<void(const std::string& channel, const void* data, std::size_t size)>;
  explicit PartJoiner(std::size_t max_message_bytes = kMaxPartedMessageBytes) : max_message_bytes_(max_message_bytes) {}
  /// Returns "" or why a part was rejected (naming its channel).
  std::string Add(const std::string& channel, const void* data, std::size_t size, const Whole& whole);
  /// Incomplete messages dropped so far, over every channel.
  long abandoned() const;

 private:
  std::size_t max_message_bytes_;
  std::map<std::string, PartAssembler> assemblers_;
};

}  // namespace rbcp::transport
