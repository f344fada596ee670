#include "cluster/quantization.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/half.h"

namespace acpca {

/// Rounds every value to the nearest half (kept as float).
void roundToHalf(std::vector<float>& values) {
  std::vector<std::uint16_t> h(values.size());
  floatToHalf(values.data(), h.data(), values.size());
  halfToFloat(h.data(), values.data(), values.size());
}

double storeCoefficients(Model& m, CoeffPrecision precision) {
  ACPCA_CHECK(m.precision == CoeffPrecision::F32 && m.coeffF16.empty() && m.coeffI8.empty(),
              "coefficients are already stored as ", coeffPrecisionName(m.precision));
  m.precision = precision;
  m.coeffScale.assign(m.clusters() ? m.firstBasisIndex(m.clusters()) : 0, 1.0f);
  if (precision == CoeffPrecision::F32) return 0;
  // Orthonormal bases: the coefficient error is the row error, so this is exact.
  double error = 0;
  const std::vector<float> exact = std::move(m.coeffF32);
  m.coeffF32.clear();
  if (precision == CoeffPrecision::F16) {
    m.coeffF16.resize(exact.size());
    floatToHalf(exact.data(), m.coeffF16.data(), exact.size());
    std::vector<float> back(exact.size());
    halfToFloat(m.coeffF16.data(), back.data(), back.size());
    for (size_t i = 0; i < exact.size(); ++i) error += std::pow(double(back[i]) - exact[i], 2);
    return error;
  }
  m.coeffI8.resize(exact.size());
  for (int c = 0; c < m.clusters(); ++c) {
    const int rank = m.ranks[c];
    const long long rows = m.rowOffsets[c + 1] - m.rowOffsets[c];
    const long long first = m.coefficientOffsets[c];
    for (int k = 0; k < rank; ++k) {
      float maxAbs = 0;
      for (long long r = 0; r < rows; ++r)
        maxAbs = std::max(maxAbs, std::abs(exact[first + r * rank + k]));
      const float scale = maxAbs > 0 ? maxAbs / 127.0f : 1.0f;
      for (long long r = 0; r < rows; ++r) {
        const long long i = first + r * rank + k;
        const float q = std::clamp(std::round(exact[i] / scale), -127.0f, 127.0f);
        m.coeffI8[i] = static_cast<std::int8_t>(q);
        error += std::pow(double(q) * scale - exact[i], 2);
      }
      m.coeffScale[m.firstBasisIndex(c) + k] = scale;
    }
  }
  return error;
}

}  // namespace acpca
