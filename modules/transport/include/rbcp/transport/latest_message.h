#pragma once
/// Subscription that keeps only the latest message of a channel. Messages are decoded with
/// DecodeMessage, so a malformed one (bad fingerprint, truncated, a negative array count or one
/// the bytes do not hold) becomes an error string naming the channel, for the node's status,
/// instead of a crash or a huge allocation. Both subscriptions hear the channel's messages whole
/// or in parts on CHANNEL/PART (message_parts.h), through the process's message faults
/// (message_faults.h), none unless RBCP_MESSAGE_FAULTS asks for them.

#include <lcm/lcm-cpp.hpp>

#include <functional>
#include <optional>
#include <string>
#include <utility>

#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/wire_check.h"

namespace rbcp::transport {

template <typename Msg>
class LatestMessage {
 public:
  /// With `keep`, decoded messages it rejects are ignored (e.g. one process's on a shared channel).
  LatestMessage(lcm::LCM& lcm, const std::string& channel, std::function<bool(const Msg&)> keep = {})
      : channel_(channel),
        keep_(std::move(keep)),
        receiver_(
            lcm, channel, [this](const void* data, std::size_t size) { Handle(data, size); },
            [this](const std::string& problem) { decode_error_ = problem; }) {}
  LatestMessage(const LatestMessage&) = delete;
  LatestMessage& operator=(const LatestMessage&) = delete;

  /// The newest message not yet taken, if any; taking it clears the "new" flag.
  std::optional<Msg> Take() {
    if (!fresh_) return std::nullopt;
    fresh_ = false;
    return latest_;
  }
  /// The newest message received, taken or not.
  const std::optional<Msg>& Latest() const { return latest_; }
  bool HasNew() const { return fresh_; }
  /// Why the latest rejected message could not be decoded; taking it clears it.
  std::optional<std::string> TakeDecodeError() { return std::exchange(decode_error_, std::nullopt); }
  long received() const { return received_; }
  const std::string& channel() const { return channel_; }

 private:
  void Handle(const void* data, std::size_t size) {
    Msg msg;
    if (auto problem = DecodeMessage(data, size, msg)) {
      decode_error_ = "cannot decode " + channel_ + " (" + std::to_string(size) + " bytes): " + *problem;
      return;
    }
    if (keep_ && !keep_(msg)) return;
    latest_ = std::move(msg);
    fresh_ = true;
    ++received_;
  }

  std::string channel_;
  std::function<bool(const Msg&)> keep_;
  std::optional<Msg> latest_;
  std::optional<std::string> decode_error_;
  bool fresh_ = false;
  long received_ = 0;
  ChannelReceiver receiver_;  // last: it calls back into the members above
};

/// Subscription that hands every message of a channel to `handle` (for channels several processes
/// share, where the newest alone is not enough). A message DecodeMessage rejects, or a part that
/// cannot belong to a whole message, goes to `reject` with the reason, naming the channel, and is
/// otherwise ignored.
template <typename Msg>
class EveryMessage {
 public:
  EveryMessage(lcm::LCM& lcm, const std::string& channel, std::function<void(const Msg&)> handle,
               std::function<void(const std::string&)> reject)
      : channel_(channel),
        handle_(std::move(handle)),
        reject_(std::move(reject)),
        receiver_(
            lcm, channel, [this](const void* data, std::size_t size) { Handle(data, size); },
            [this](const std::string& problem) {
              ++rejected_;
              if (reject_) reject_(problem);
            }) {}
  EveryMessage(const EveryMessage&) = delete;
  EveryMessage& operator=(const EveryMessage&) = delete;
  long rejected() const { return rejected_; }

 private:
  void Handle(const void* data, std::size_t size) {
    Msg msg;
    const std::optional<std::string> problem = DecodeMessage(data, size, msg);
    if (!problem) {
      handle_(msg);
      return;
    }
    ++rejected_;
    if (reject_) reject_("cannot decode " + channel_ + " (" + std::to_string(size) + " bytes): " + *problem);
  }

  std::string channel_;
  std::function<void(const Msg&)> handle_;
  std::function<void(const std::string&)> reject_;
  long rejected_ = 0;
  ChannelReceiver receiver_;  // last: it calls back into the members above
};

}  // namespace rbcp::transport
