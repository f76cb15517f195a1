#pragma once
/// Subscription that keeps only the latest message of a channel. Messages are decoded with
/// DecodeMessage, so a malformed one (bad fingerprint, truncated, a negative array count or one
/// the bytes do not hold) becomes an error string naming the channel, for the node's status,
/// instead of a crash or a huge allocation. Both subscriptions receive through the process's
/// message faults (message_faults.h), none unless RBCP_MESSAGE_FAULTS asks for them.

#include <lcm/lcm-cpp.hpp>

#include <functional>
#include <optional>
#include <string>
#include <utility>

#include "rbcp/transport/message_faults.h"
#include "rbcp/transport/wire_check.h"

namespace rbcp::transport {

template <typename Msg>
class LatestMessage {
 public:
  /// With `keep`, decoded messages it rejects are ignored (e.g. one process's on a shared channel).
  LatestMessage(lcm::LCM& lcm, const std::string& channel, std::function<bool(const Msg&)> keep = {})
      : channel_(channel), keep_(std::move(keep)), faults_(channel, ProcessMessageFaults()) {
    subscription_ = lcm.subscribe(channel, &LatestMessage::OnMessage, this);
    lcm_ = &lcm;
  }
  ~LatestMessage() {
    if (lcm_ && subscription_) lcm_->unsubscribe(subscription_);
  }
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
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    faults_.Receive(rbuf->data, rbuf->data_size, [this](const void* data, std::size_t size) { Handle(data, size); });
  }
  void Handle(const void* data, std::size_t size) {
    Msg msg;
    const std::string problem = DecodeMessage(data, size, msg);
    if (!problem.empty()) {
      decode_error_ = "cannot decode " + channel_ + " (" + std::to_string(size) + " bytes): " + problem;
      return;
    }
    if (keep_ && !keep_(msg)) return;
    latest_ = std::move(msg);
    fresh_ = true;
    ++received_;
  }

  std::string channel_;
  std::function<bool(const Msg&)> keep_;
  ReceiveFaults faults_;
  lcm::LCM* lcm_ = nullptr;
  lcm::Subscription* subscription_ = nullptr;
  std::optional<Msg> latest_;
  std::optional<std::string> decode_error_;
  bool fresh_ = false;
  long received_ = 0;
};

/// Subscription that hands every message of a channel to `handle` (for channels several processes
/// share, where the newest alone is not enough). A message DecodeMessage rejects goes to `reject`
/// with the reason, naming the channel, and is otherwise ignored.
template <typename Msg>
class EveryMessage {
 public:
  EveryMessage(lcm::LCM& lcm, const std::string& channel, std::function<void(const Msg&)> handle,
               std::function<void(const std::string&)> reject)
      : lcm_(lcm), channel_(channel), handle_(std::move(handle)), reject_(std::move(reject)),
        faults_(channel, ProcessMessageFaults()) {
    subscription_ = lcm.subscribe(channel, &EveryMessage::OnMessage, this);
  }
  ~EveryMessage() {
    if (subscription_) lcm_.unsubscribe(subscription_);
  }
  EveryMessage(const EveryMessage&) = delete;
  EveryMessage& operator=(const EveryMessage&) = delete;
  long rejected() const { return rejected_; }

 private:
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    faults_.Receive(rbuf->data, rbuf->data_size, [this](const void* data, std::size_t size) { Handle(data, size); });
  }
  void Handle(const void* data, std::size_t size) {
    Msg msg;
    const std::string problem = DecodeMessage(data, size, msg);
    if (problem.empty()) {
      handle_(msg);
      return;
    }
    ++rejected_;
    if (reject_) reject_("cannot decode " + channel_ + " (" + std::to_string(size) + " bytes): " + problem);
  }

  lcm::LCM& lcm_;
  std::string channel_;
  std::function<void(const Msg&)> handle_;
  std::function<void(const std::string&)> reject_;
  ReceiveFaults faults_;
  lcm::Subscription* subscription_ = nullptr;
  long rejected_ = 0;
};

}  // namespace rbcp::transport
