#include "rbcp/core/format.h"

#include <iomanip>
#include <sstream>

namespace rbcp {

std::string FixedNumber(double value, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << value;
  return os.str();
}

}  // namespace rbcp
