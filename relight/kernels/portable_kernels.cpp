// The relighter's loops in plain C++: the reference the vector kernels are
// tested against, and the path on CPUs without AVX2.
#include "relight/kernels/kernel_table.h"
#include "relight/kernels/scalar_loops.h"

namespace acpca::kernels {

namespace {

void dotRgbPortable(const float* column, const float* const light[3], int length, float out[3]) {
  out[0] = out[1] = out[2] = 0;
  dotRgbScalar(column, light, 0, length, out);
}

void dotRgbColumnsPortable(const float* columns, int count, const float* const light[3], int length,
                           float* out) {
  for (int i = 0; i < count; ++i)
    dotRgbPortable(columns + static_cast<size_t>(i) * length, light, length, out + 3 * i);
}

void dotSegmentsPortable(const std::uint16_t* values, const std::uint16_t* segments, int count,
                         const float* const light[3], float out[3]) {
  out[0] = out[1] = out[2] = 0;
  for (int i = 0; i < count; ++i)
    for (int lane = 0; lane < kChunkRows; ++lane) {
      const float v = widen(values[i * kChunkRows + lane]);
      for (int c = 0; c < 3; ++c) out[c] += v * light[c][segments[i] * kChunkRows + lane];
    }
}

template <typename T>
void shadeChunkPortable(const T* coefficients, const float* lighting, int rank, const float base[3],
                        float out[3][kChunkRows]) {
  for (int c = 0; c < 3; ++c)
    for (int lane = 0; lane < kChunkRows; ++lane) out[c][lane] = base[c];
  for (int k = 0; k < rank; ++k)
    for (int lane = 0; lane < kChunkRows; ++lane) {
      const float u = widen(coefficients[k * kChunkRows + lane]);
      for (int c = 0; c < 3; ++c) out[c][lane] += u * lighting[3 * k + c];
    }
}

template <typename T>
void shadeChunkOnePortable(const T* coefficients, const float* transport, int rank, float base,
                           float out[kChunkRows]) {
  for (int lane = 0; lane < kChunkRows; ++lane) out[lane] = base;
  for (int k = 0; k < rank; ++k)
    for (int lane = 0; lane < kChunkRows; ++lane)
      out[lane] += widen(coefficients[k * kChunkRows + lane]) * transport[k];
}

}  // namespace

const KernelTable& portableKernels() {
  static const KernelTable table{dotRgbPortable,
                                 dotRgbColumnsPortable,
                                 dotSegmentsPortable,
                                 shadeChunkPortable<float>,
                                 shadeChunkPortable<std::uint16_t>,
                                 shadeChunkPortable<std::int8_t>,
                                 shadeChunkOnePortable<float>,
                                 shadeChunkOnePortable<std::uint16_t>,
                                 shadeChunkOnePortable<std::int8_t>};
  return table;
}

}  // namespace acpca::kernels
