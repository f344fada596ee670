#pragma once
// IEEE 754 binary16 conversion for the transport and model files. Bulk loops use
// the F16C instructions when the build targets them (x86-64-v3), else Eigen::half.
#include <cstddef>
#include <cstdint>

namespace acpca {

/// Largest finite half; larger magnitudes are clamped so files never hold Inf.
constexpr float kHalfMax = 65504.0f;

void floatToHalf(const float* in, std::uint16_t* out, std::size_t count);
/// IEEE conversion as image files take it (OpenEXR's half): rounded to
/// nearest even, magnitudes past the largest half become Inf, NaN stays NaN.
void floatToHalfIeee(const float* in, std::uint16_t* out, std::size_t count);
void halfToFloat(const std::uint16_t* in, float* out, std::size_t count);

}  // namespace acpca
