#pragma once
// IEEE 754 binary16 conversion for the transport and model files. Bulk loops use
// the F16C instructions when the build targets them (x86-64-v3), else Eigen::half.
#include <cstddef>
#include <cstdint>
#if defined(__F16C__)
#include <immintrin.h>
#endif

namespace acpca {

/// Largest finite half; larger magnitudes are clamped so files never hold Inf.
constexpr float kHalfMax = 65504.0f;

void floatToHalf(const float* in, std::uint16_t* out, std::size_t count);
/// IEEE conversion as image files take it (OpenEXR's half): rounded to
/// nearest even, magnitudes past the largest half become Inf, NaN stays NaN.
void floatToHalfIeee(const float* in, std::uint16_t* out, std::size_t count);
void halfToFloat(const std::uint16_t* in, float* out, std::size_t count);

/// 16 halves as floats, inline, for loops that widen a row of 16 as they
/// read it (exact either way: any float holds a half).
inline void halfToFloat16(const std::uint16_t* in, float* out) {
#if defined(__F16C__)
  _mm256_storeu_ps(out, _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in))));
  _mm256_storeu_ps(out + 8,
                   _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in + 8))));
#else
  halfToFloat(in, out, 16);
#endif
}

}  // namespace acpca
