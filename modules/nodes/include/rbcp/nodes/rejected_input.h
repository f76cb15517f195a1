#pragma once
/// Why a planner process rejected an input message: it answers with FAILED and Describe() on
/// STATUS, and handles the next valid message as usual.

#include <optional>
#include <string>
#include <utility>

#include "rbcp/transport/sim_clock.h"

namespace rbcp::nodes {

struct RejectedInput {
  enum class Kind {
    kUndecodable,  ///< its bytes do not decode into the message (detail)
    kTime,         ///< its utime is not taken as the simulated time (time)
    kContent,      ///< what it holds fails validation: a mesh, surfaces, a path, a request (detail)
  };
  Kind kind = Kind::kContent;
  std::string detail;                           ///< kUndecodable, kContent: what was found, naming the message
  std::optional<transport::RejectedTime> time;  ///< kTime

  static RejectedInput Undecodable(std::string detail) { return {Kind::kUndecodable, std::move(detail), std::nullopt}; }
  static RejectedInput Content(std::string detail) { return {Kind::kContent, std::move(detail), std::nullopt}; }
  static RejectedInput Time(transport::RejectedTime time) { return {Kind::kTime, "", std::move(time)}; }

  std::string Describe() const { return time ? time->Describe() : detail; }
};

}  // namespace rbcp::nodes
