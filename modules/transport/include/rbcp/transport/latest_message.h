#pragma once
/// Subscription that keeps only the latest message of a channel. Decoding happens inside the
/// callback under a try/catch, so a malformed message (bad fingerprint, truncated, negative
/// array count) becomes an error string for the node's status instead of a crash.

#include <lcm/lcm-cpp.hpp>

#include <functional>
#include <optional>
#include <string>
#include <utility>

namespace rbcp::transport {

template <typename Msg>
class LatestMessage {
 public:
  /// With `keep`, decoded messages it rejects are ignored (e.g. one process's on a shared channel).
  LatestMessage(lcm::LCM& lcm, const std::string& channel, std::function<bool(const Msg&)> keep = {})
      : channel_(channel), keep_(std::move(keep)) {
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
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    Msg msg;
    int status = -1;
    try {
      status = msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size));
    } catch (const std::exception& e) {
      decode_error_ = "cannot decode " + channel + ": " + e.what();
      return;
    }
    if (status < 0) {
      decode_error_ = "cannot decode " + channel + " (" + std::to_string(rbuf->data_size) +
                      " bytes): wrong type, truncated or malformed";
      return;
    }
    if (keep_ && !keep_(msg)) return;
    latest_ = std::move(msg);
    fresh_ = true;
    ++received_;
  }

  std::string channel_;
  std::function<bool(const Msg&)> keep_;
  lcm::LCM* lcm_ = nullptr;
  lcm::Subscription* subscription_ = nullptr;
  std::optional<Msg> latest_;
  std::optional<std::string> decode_error_;
  bool fresh_ = false;
  long received_ = 0;
};

}  // namespace rbcp::transport
