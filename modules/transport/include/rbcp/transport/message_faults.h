#pragma once
/// Network faults on purpose: received messages dropped, duplicated or held back behind the next
/// one of their channel (reordered), at configured rates, to test that the processes survive a
/// lossy link and never act on a stale or superseded message. Every subscription of the
/// transport (LatestMessage, EveryMessage) receives through a ReceiveFaults; the process-wide
/// rates come from the environment variable RBCP_MESSAGE_FAULTS ("drop=0.1,duplicate=0.05,
/// reorder=0.05,seed=3"; unset or empty: no faults), so a launcher sets them for every process.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace rbcp::transport {

/// The environment variable that holds the process's fault rates.
inline constexpr const char* kMessageFaultsEnv = "RBCP_MESSAGE_FAULTS";

struct MessageFaultRates {
  double drop = 0.0;       ///< probability that a received message is lost
  double duplicate = 0.0;  ///< probability that it is handled twice
  double reorder = 0.0;    ///< probability that it is held back and handled after the next one
  std::uint64_t seed = 1;  ///< seed of every subscription's draws (mixed with its channel name)
  bool Any() const { return drop > 0.0 || duplicate > 0.0 || reorder > 0.0; }
};

/// Reads "key=value,..." with keys drop, duplicate, reorder (probabilities, together below 1)
/// and seed (a non-negative integer). Throws InputError naming the bad part.
MessageFaultRates ParseMessageFaults(const std::string& spec);

/// The rates of this process, read from RBCP_MESSAGE_FAULTS once (nullopt: no faults). Throws
/// InputError when the variable is malformed; OpenLcm() calls it, so a bad value stops a process
/// at its start with the reason.
const std::optional<MessageFaultRates>& ProcessMessageFaults();

/// One subscription's faults: decides the fate of each received message with its own seeded
/// generator and hands the bytes to `deliver` zero, one or two times, a held message after the
/// next one of the channel.
class ReceiveFaults {
 public:
  using Deliver = std::function<void(const void* data, std::size_t size)>;
  ReceiveFaults(const std::string& channel, std::optional<MessageFaultRates> rates);
  void Receive(const void* data, std::size_t size, const Deliver& deliver);

  long dropped() const { return dropped_; }
  long duplicated() const { return duplicated_; }
  long reordered() const { return reordered_; }

 private:
  std::optional<MessageFaultRates> rates_;
  std::mt19937_64 rng_;
  std::optional<std::vector<std::uint8_t>> held_;
  long dropped_ = 0;
  long duplicated_ = 0;
  long reordered_ = 0;
};

}  // namespace rbcp::transport
