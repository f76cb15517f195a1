#pragma once
/// Numbers in messages and reports.

#include <string>

namespace rbcp {

/// `value` in fixed notation with `digits` decimals, e.g. FixedNumber(0.03049, 3) == "0.030".
std::string FixedNumber(double value, int digits = 3);

}  // namespace rbcp
