#pragma once
// Layout constants and checksum of the limb database cache file.
//
// File layout (native endianness; every field 8-byte aligned):
//   header (kHeaderBytes): magic "RBCPLDB\0", uint32 format version, uint32 header size,
//                          uint64 key, uint64 payload size, uint64 payload checksum, uint64 zero
//   payload:               double resolution, then per leg (LF, RF, LH, RH):
//                          uint64 samples N, uint64 cells C, int64 draws,
//                          double q[3N], double foot[3N], double score[N], CellRecord cells[C]

#include <cstddef>
#include <cstdint>

namespace rbcp::limb_database_detail {

inline constexpr char kCacheMagic[8] = {'R', 'B', 'C', 'P', 'L', 'D', 'B', '\0'};
inline constexpr std::uint32_t kCacheFormatVersion = 1;
inline constexpr std::size_t kCacheHeaderBytes = 48;
inline constexpr std::size_t kCacheKeyOffset = 16;
inline constexpr std::size_t kCacheChecksumOffset = 32;
/// Bytes of the payload before the first leg, and of a leg's header.
inline constexpr std::size_t kCachePayloadPreambleBytes = 8;
inline constexpr std::size_t kCacheLegHeaderBytes = 24;

/// 64-bit hash over 8-byte words (xor, odd multiply, xor-shift: each step is a bijection of the
/// state, so a change confined to one word always changes the result).
std::uint64_t Hash64(const char* data, std::size_t size);

}  // namespace rbcp::limb_database_detail
