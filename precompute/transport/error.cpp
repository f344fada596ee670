#include "precompute/transport/error.h"

namespace acpca {

void failCheck(const char* condition, const char* file, int line, const std::string& detail) {
  std::string message = concat("internal check failed: ", condition, " at ", file, ":", line);
  if (!detail.empty()) message += " (" + detail + ")";
  throw std::logic_error(message);
}

}  // namespace acpca
