#include "core/statistics.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace acpca {

double relativeL2(const std::vector<float>& b, const std::vector<float>& reference) {
  ACPCA_CHECK(b.size() == reference.size(), "sizes ", b.size(), " and ", reference.size());
  double diff = 0, norm = 0;
  for (size_t i = 0; i < b.size(); ++i) {
    diff += (double(b[i]) - reference[i]) * (double(b[i]) - reference[i]);
    norm += double(reference[i]) * reference[i];
  }
  return norm > 0 ? std::sqrt(diff / norm) : std::sqrt(diff);
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

}  // namespace acpca
