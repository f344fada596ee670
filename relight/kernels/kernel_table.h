#pragma once
// The relighter's inner loops at each instruction-set level, as tables of
// function pointers: relight_kernels.cpp picks one at run time.
#include <cstdint>

#include "relight/relight_kernels.h"

namespace acpca::kernels {

using ShadeF32 = void (*)(const float*, const float*, int, const float[3], float[3][kChunkRows]);
using ShadeF16 = void (*)(const std::uint16_t*, const float*, int, const float[3],
                          float[3][kChunkRows]);
using ShadeI8 = void (*)(const std::int8_t*, const float*, int, const float[3],
                         float[3][kChunkRows]);
template <typename T>
using ShadeOne = void (*)(const T*, const float*, int, float, float[kChunkRows]);

struct KernelTable {
  void (*dotRgb)(const float*, const float* const[3], int, float[3]);
  void (*dotRgbColumns)(const float*, int, const float* const[3], int, float*);
  void (*dotSegmentsRgb)(const std::uint16_t*, const std::uint16_t*, int, const float* const[3],
                         float[3]);
  ShadeF32 shadeF32;
  ShadeF16 shadeF16;
  ShadeI8 shadeI8;
  ShadeOne<float> shadeOneF32;
  ShadeOne<std::uint16_t> shadeOneF16;
  ShadeOne<std::int8_t> shadeOneI8;
};

/// Plain C++: every machine.
const KernelTable& portableKernels();
/// nullptr where the build does not target AVX2 + FMA + F16C.
const KernelTable* avx2Kernels();
/// nullptr where the compiler cannot emit AVX-512F; the caller checks the CPU.
const KernelTable* avx512Kernels();

}  // namespace acpca::kernels
