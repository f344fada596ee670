#include "lighting/spec_parsing.h"

#include <cmath>

#include "core/error.h"

namespace acpca {

double parseFiniteNumber(const std::string& text, const std::string& parameter,
                         const std::string& spec) {
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value))
    throw ParameterError(parameter, spec, concat("'", text, "' is not a finite number"));
  return value;
}

void requireFinite(double value, const std::string& parameter) {
  if (!std::isfinite(value))
    throw ParameterError(parameter, concat(value), concat("'", value, "' is not a finite number"));
}

SpecParseCounts& specParseCounts() {
  static SpecParseCounts counts;
  return counts;
}

}  // namespace acpca
