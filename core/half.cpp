#include "core/half.h"

#include <Eigen/Core>
#include <algorithm>

#if defined(__F16C__)
#include <immintrin.h>
#endif

namespace acpca {

void floatToHalf(const float* in, std::uint16_t* out, std::size_t count) {
  std::size_t i = 0;
#if defined(__F16C__)
  const __m256 hi = _mm256_set1_ps(kHalfMax), lo = _mm256_set1_ps(-kHalfMax);
  for (; i + 8 <= count; i += 8) {
    const __m256 v = _mm256_min_ps(_mm256_max_ps(_mm256_loadu_ps(in + i), lo), hi);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i),
                     _mm256_cvtps_ph(v, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
  }
#endif
  for (; i < count; ++i)
    out[i] =
        Eigen::numext::bit_cast<std::uint16_t>(Eigen::half(std::clamp(in[i], -kHalfMax, kHalfMax)));
}

void floatToHalfIeee(const float* in, std::uint16_t* out, std::size_t count) {
  std::size_t i = 0;
#if defined(__F16C__)
  for (; i + 8 <= count; i += 8)
    _mm_storeu_si128(
        reinterpret_cast<__m128i*>(out + i),
        _mm256_cvtps_ph(_mm256_loadu_ps(in + i), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
#endif
  for (; i < count; ++i) out[i] = Eigen::numext::bit_cast<std::uint16_t>(Eigen::half(in[i]));
}

void halfToFloat(const std::uint16_t* in, float* out, std::size_t count) {
  std::size_t i = 0;
#if defined(__F16C__)
  for (; i + 8 <= count; i += 8)
    _mm256_storeu_ps(out + i,
                     _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in + i))));
#endif
  for (; i < count; ++i) out[i] = static_cast<float>(Eigen::numext::bit_cast<Eigen::half>(in[i]));
}

}  // namespace acpca
