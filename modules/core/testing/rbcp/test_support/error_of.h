#pragma once
/// Test helper: the message of the InputError a call throws.

#include <functional>
#include <string>

#include "rbcp/core/error.h"

namespace rbcp::test_support {

/// What `f` throws as InputError, or "" when it throws nothing.
inline std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace rbcp::test_support
