// The libFuzzer target of one entry of rbcp/fuzz/fuzz_entries.h, named at compile time
// (RBCP_FUZZ_ENTRY); modules/fuzz/CMakeLists.txt builds one fuzz_NAME per entry.
#include <cstdio>
#include <cstdlib>

#include "rbcp/fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rbcp::fuzz::Entry* const entry = rbcp::fuzz::FindEntry(RBCP_FUZZ_ENTRY);
  if (entry == nullptr) {
    std::fprintf(stderr, "fuzz target: no entry named %s\n", RBCP_FUZZ_ENTRY);
    std::abort();
  }
  entry->run(data, size);  // a rejected input is fine; anything that escapes is a finding
  return 0;
}
