#pragma once
/// The crawl order LH, LF, RH, RF, which also breaks ties between legs.

#include <array>

#include "rbcp/core/leg.h"

namespace rbcp::contact_planner_detail {

/// The crawl order, also used to break ties between equally stretched legs.
inline constexpr std::array<Leg, kNumLegs> kTieOrder = {Leg::kLH, Leg::kLF, Leg::kRH, Leg::kRF};

/// Position of `leg` in kTieOrder (lower first).
inline int TieRank(Leg leg) {
  for (int i = 0; i < kNumLegs; ++i) {
    if (kTieOrder[static_cast<std::size_t>(i)] == leg) return i;
  }
  return kNumLegs;
}

/// The leg that steps after `leg` in the crawl order LH, LF, RH, RF.
inline Leg CrawlNext(Leg leg) { return kTieOrder[static_cast<std::size_t>((TieRank(leg) + 1) % kNumLegs)]; }

/// The leg that steps before `leg` in the crawl order LH, LF, RH, RF.
inline Leg CrawlPrevious(Leg leg) {
  return kTieOrder[static_cast<std::size_t>((TieRank(leg) + kNumLegs - 1) % kNumLegs)];
}

}  // namespace rbcp::contact_planner_detail
