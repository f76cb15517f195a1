#include "rbcp/transport/message_faults.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "rbcp/core/error.h"

namespace rbcp::transport {
namespace {

/// FNV-1a: a channel name's share of its subscription's seed, the same on every machine.
std::uint64_t NameHash(const std::string& name) {
  std::uint64_t h = 1469598103934665603ull;
  for (const char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

std::string Where(const std::string& spec) { return std::string(kMessageFaultsEnv) + " '" + spec + "'"; }

}  // namespace

MessageFaultRates ParseMessageFaults(const std::string& spec) {
  MessageFaultRates rates;
  std::istringstream parts(spec);
  std::string part;
  while (std::getline(parts, part, ',')) {
    if (part.empty()) continue;
    const std::size_t eq = part.find('=');
    if (eq == std::string::npos) {
      throw InputError(Where(spec) + ": expected key=value, got '" + part + "'");
    }
    const std::string key = part.substr(0, eq);
    const std::string value = part.substr(eq + 1);
    errno = 0;
    char* end = nullptr;
    if (key == "seed") {
      const unsigned long long seed = std::strtoull(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || errno != 0 || value[0] == '-') {
        throw InputError(Where(spec) + ": 'seed' expected a non-negative integer, got '" + value + "'");
      }
      rates.seed = seed;
      continue;
    }
    double* target = key == "drop" ? &rates.drop : key == "duplicate" ? &rates.duplicate
                                                 : key == "reorder"   ? &rates.reorder
                                                                      : nullptr;
    if (!target) {
      throw InputError(Where(spec) + ": unknown key '" + key + "' (keys: drop, duplicate, reorder, seed)");
    }
    const double p = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || errno != 0 || !std::isfinite(p) || p < 0.0 || p >= 1.0) {
      throw InputError(Where(spec) + ": '" + key + "' expected a probability in [0, 1), got '" + value + "'");
    }
    *target = p;
  }
  if (!(rates.drop + rates.duplicate + rates.reorder < 1.0)) {
    throw InputError(Where(spec) + ": drop + duplicate + reorder expected below 1");
  }
  return rates;
}

const std::optional<MessageFaultRates>& ProcessMessageFaults() {
  static const std::optional<MessageFaultRates> rates = []() -> std::optional<MessageFaultRates> {
    const char* spec = std::getenv(kMessageFaultsEnv);
    if (!spec || !*spec) return std::nullopt;
    const MessageFaultRates r = ParseMessageFaults(spec);
    if (!r.Any()) return std::nullopt;
    return r;
  }();
  return rates;
}

ReceiveFaults::ReceiveFaults(const std::string& channel, std::optional<MessageFaultRates> rates)
    : rates_(rates), rng_(rates ? rates->seed ^ NameHash(channel) : 0) {}

void ReceiveFaults::Receive(const void* data, std::size_t size, const Deliver& deliver) {
  if (!rates_) {
    deliver(data, size);
    return;
  }
  const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
  if (u < rates_->drop) {
    ++dropped_;
    return;  // a message held back stays held until one gets through
  }
  if (u < rates_->drop + rates_->duplicate) {
    ++duplicated_;
    deliver(data, size);
    deliver(data, size);
  } else if (u < rates_->drop + rates_->duplicate + rates_->reorder && !held_) {
    ++reordered_;
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    held_.emplace(bytes, bytes + size);
    return;
  } else {
    deliver(data, size);
  }
  if (held_) {
    // The message held back comes after the newer one.
    const std::vector<std::uint8_t> late = std::move(*held_);
    held_.reset();
    deliver(late.data(), late.size());
  }
}

}  // namespace rbcp::transport
