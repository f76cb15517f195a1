#pragma once
/// Ids that must not collide with another process's or another run's: a plan request's id, the
/// sender id of a message sent in parts.

#include <cstdint>
#include <limits>
#include <random>

namespace rbcp::transport {

/// A random id in [1, INT64_MAX] from the operating system's entropy (not from a seed: two runs
/// with the same seed must still tell their messages apart).
inline int64_t RandomId() {
  std::random_device device;
  std::uniform_int_distribution<int64_t> id(1, std::numeric_limits<int64_t>::max());
  return id(device);
}

}  // namespace rbcp::transport
