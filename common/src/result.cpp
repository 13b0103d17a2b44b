#include "annex/common/result.h"

namespace annex {

std::string Error::format() const {
  std::string out;
  if (!location.origin.empty()) {
    out += location.origin;
    if (location.line > 0) {
      out += ':' + std::to_string(location.line);
      if (location.column > 0) out += ':' + std::to_string(location.column);
    }
    out += ": ";
  }
  out += "error: " + message;
  return out;
}

}  // namespace annex
