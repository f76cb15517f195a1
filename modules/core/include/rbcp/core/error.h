#pragma once
/// Error conventions shared by every library.
///  - InputError: bad input or config, thrown at load time with "expected X, got Y".
///  - RBCP_CHECK: an internal invariant, always on; a failure is a bug and throws InvariantError.
///  - Expected planning failures are not exceptions: they are status values with a reason.

#include <sstream>
#include <stdexcept>
#include <string>

namespace rbcp {

/// Bad input (file, message or configuration); the message names the source and the problem.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A broken internal invariant.
class InvariantError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

namespace detail {
[[noreturn]] inline void FailCheck(const char* expr, const char* file, int line, const std::string& msg) {
  std::ostringstream os;
  os << file << ":" << line << ": invariant failed: " << expr;
  if (!msg.empty()) os << " (" << msg << ")";
  throw InvariantError(os.str());
}
}  // namespace detail

}  // namespace rbcp

#define RBCP_CHECK(cond, msg)                                                          \
  do {                                                                                 \
    if (!(cond)) ::rbcp::detail::FailCheck(#cond, __FILE__, __LINE__, std::string(msg)); \
  } while (0)
