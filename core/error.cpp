#include "core/error.h"

namespace acpca {

void failCheck(const char* condition, const char* file, int line, const std::string& detail) {
  if (detail.empty())
    throw std::logic_error(concat("internal check failed: ", condition, " at ", file, ":", line));
  throw std::logic_error(
      concat("internal check failed: ", condition, " at ", file, ":", line, " (", detail, ")"));
}

}  // namespace acpca
