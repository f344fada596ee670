#pragma once
// Scalar forms of the relighter's loops: the portable kernels, and the tails
// the vector kernels leave.
#include <cstdint>

#include "core/half.h"
#include "relight/relight_kernels.h"

namespace acpca::kernels {

inline float widen(float v) {
  return v;
}
inline float widen(std::uint16_t v) {
  float f;
  halfToFloat(&v, &f, 1);
  return f;
}
inline float widen(std::int8_t v) {
  return static_cast<float>(v);
}

/// out[c] += sum_{begin <= j < end} column[j] light[c][j].
template <typename T>
void dotRgbScalar(const T* column, const float* const light[3], int begin, int end, float out[3]) {
  for (int j = begin; j < end; ++j) {
    const float v = widen(column[j]);
    for (int c = 0; c < 3; ++c) out[c] += v * light[c][j];
  }
}

}  // namespace acpca::kernels
