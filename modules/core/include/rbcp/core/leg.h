#pragma once
/// Leg naming: left/right x fore/hind, in the order LF, RF, LH, RH used by every array of four.

#include <array>
#include <optional>
#include <string_view>

namespace rbcp {

enum class Leg : int { kLF = 0, kRF = 1, kLH = 2, kRH = 3 };

inline constexpr int kNumLegs = 4;
inline constexpr std::array<Leg, kNumLegs> kAllLegs = {Leg::kLF, Leg::kRF, Leg::kLH, Leg::kRH};

inline constexpr int Index(Leg leg) { return static_cast<int>(leg); }

inline constexpr std::string_view LegName(Leg leg) {
  constexpr std::array<std::string_view, kNumLegs> kNames = {"LF", "RF", "LH", "RH"};
  return kNames[static_cast<std::size_t>(Index(leg))];
}

/// +1 for fore legs, -1 for hind legs.
inline constexpr double ForeSign(Leg leg) { return (leg == Leg::kLF || leg == Leg::kRF) ? 1.0 : -1.0; }
/// +1 for left legs, -1 for right legs.
inline constexpr double LeftSign(Leg leg) { return (leg == Leg::kLF || leg == Leg::kLH) ? 1.0 : -1.0; }

inline std::optional<Leg> LegFromName(std::string_view name) {
  for (Leg leg : kAllLegs) {
    if (LegName(leg) == name) return leg;
  }
  return std::nullopt;
}

}  // namespace rbcp
