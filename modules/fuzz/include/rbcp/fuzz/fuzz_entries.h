#pragma once
/// The entry points of untrusted input, each as a function of raw bytes: what the libFuzzer
/// targets (modules/fuzz/targets, built by `tools/fuzz`) and the regression test of their findings
/// (tests/fuzz_regressions/NAME/) feed.
///
/// An entry runs the bytes through the code the programs run on such input (a scenario file, a
/// mesh file, a plan JSON file, an LCM message as a node decodes and validates it) and reports
/// whether it was accepted or rejected with the project's error (InputError, or the reason a
/// message cannot be decoded). Anything else escapes: another exception, a crash, a sanitizer
/// report, a hang or a huge allocation is a bug.

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rbcp::fuzz {

/// What an entry made of one input.
struct Outcome {
  bool accepted = false;
  std::string reason;  ///< why it was rejected; empty when accepted
};

using EntryFunction = Outcome (*)(const std::uint8_t* data, std::size_t size);

struct Entry {
  const char* name;  ///< the fuzz target's name (fuzz_NAME) and its regression folder's
  const char* what;  ///< the input and the code it goes through, for listings
  EntryFunction run;
};

/// Every entry, in a fixed order.
const std::vector<Entry>& Entries();

/// The records of a lcm_message_part input: each a 2-byte little-endian length and that many
/// bytes (the last one cut short by the input's end), as (offset, length) pairs.
std::vector<std::pair<std::size_t, std::size_t>> SplitPartRecords(const std::uint8_t* data, std::size_t size);

/// The entry called `name`, nullptr if there is none.
const Entry* FindEntry(const std::string& name);

}  // namespace rbcp::fuzz
