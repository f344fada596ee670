// The relighter's loops on AVX-512F: a chunk of 16 rows is one 16-float vector,
// so a stored value costs three FMAs at twice AVX2's width, and 16 halves widen
// in one instruction. Compiled per function (target attribute), picked at run
// time when the CPU has AVX-512F; the rest of the build stays x86-64-v3.
#include "relight/kernels/kernel_table.h"
#include "relight/kernels/scalar_loops.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// GCC 12 warns inside its own AVX-512 conversion intrinsics (their
// deliberately undefined pass-through operand) once they are inlined here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>

#define ACPCA_AVX512 __attribute__((target("avx512f")))

namespace acpca::kernels {

namespace {

ACPCA_AVX512 inline __m512 load16(const float* p) {
  return _mm512_loadu_ps(p);
}
ACPCA_AVX512 inline __m512 load16(const std::uint16_t* p) {
  return _mm512_cvtph_ps(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)));
}
ACPCA_AVX512 inline __m512 load16(const std::int8_t* p) {
  return _mm512_cvtepi32_ps(
      _mm512_cvtepi8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))));
}

template <typename T>
ACPCA_AVX512 void shadeChunkAvx512(const T* coefficients, const float* lighting, int rank,
                                   const float base[3], float out[3][kChunkRows]) {
  // Four accumulator sets (k mod 4): twelve independent FMA chains cover the
  // FMA latency on both ports. Named variables keep them in registers.
  __m512 r0 = _mm512_set1_ps(base[0]), g0 = _mm512_set1_ps(base[1]), b0 = _mm512_set1_ps(base[2]);
  __m512 r1 = _mm512_setzero_ps(), g1 = r1, b1 = r1, r2 = r1, g2 = r1, b2 = r1, r3 = r1, g3 = r1,
         b3 = r1;
  int k = 0;
  for (; k + 4 <= rank; k += 4) {
    const float* l = lighting + 3 * k;
    const T* u = coefficients + k * kChunkRows;
    __m512 v = load16(u);
    r0 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[0]), r0);
    g0 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[1]), g0);
    b0 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[2]), b0);
    v = load16(u + kChunkRows);
    r1 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[3]), r1);
    g1 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[4]), g1);
    b1 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[5]), b1);
    v = load16(u + 2 * kChunkRows);
    r2 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[6]), r2);
    g2 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[7]), g2);
    b2 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[8]), b2);
    v = load16(u + 3 * kChunkRows);
    r3 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[9]), r3);
    g3 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[10]), g3);
    b3 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[11]), b3);
  }
  for (; k < rank; ++k) {
    const float* l = lighting + 3 * k;
    const __m512 v = load16(coefficients + k * kChunkRows);
    r0 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[0]), r0);
    g0 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[1]), g0);
    b0 = _mm512_fmadd_ps(v, _mm512_set1_ps(l[2]), b0);
  }
  _mm512_storeu_ps(out[0], _mm512_add_ps(_mm512_add_ps(r0, r1), _mm512_add_ps(r2, r3)));
  _mm512_storeu_ps(out[1], _mm512_add_ps(_mm512_add_ps(g0, g1), _mm512_add_ps(g2, g3)));
  _mm512_storeu_ps(out[2], _mm512_add_ps(_mm512_add_ps(b0, b1), _mm512_add_ps(b2, b3)));
}

/// out[3 i + c] = column i . light[c] for four columns at once (they share the
/// loads of light), 16 entries a step; the tail is scalar.
ACPCA_AVX512 void dotRgbFourAvx512(const float* columns, const float* const light[3], int length,
                                   float* out) {
  const float* col[4] = {columns, columns + length, columns + 2 * static_cast<size_t>(length),
                         columns + 3 * static_cast<size_t>(length)};
  __m512 a00 = _mm512_setzero_ps(), a01 = a00, a02 = a00, a10 = a00, a11 = a00, a12 = a00,
         a20 = a00, a21 = a00, a22 = a00, a30 = a00, a31 = a00, a32 = a00;
  int j = 0;
  for (; j + 16 <= length; j += 16) {
    const __m512 l0 = _mm512_loadu_ps(light[0] + j), l1 = _mm512_loadu_ps(light[1] + j),
                 l2 = _mm512_loadu_ps(light[2] + j);
    __m512 v = _mm512_loadu_ps(col[0] + j);
    a00 = _mm512_fmadd_ps(v, l0, a00), a01 = _mm512_fmadd_ps(v, l1, a01);
    a02 = _mm512_fmadd_ps(v, l2, a02);
    v = _mm512_loadu_ps(col[1] + j);
    a10 = _mm512_fmadd_ps(v, l0, a10), a11 = _mm512_fmadd_ps(v, l1, a11);
    a12 = _mm512_fmadd_ps(v, l2, a12);
    v = _mm512_loadu_ps(col[2] + j);
    a20 = _mm512_fmadd_ps(v, l0, a20), a21 = _mm512_fmadd_ps(v, l1, a21);
    a22 = _mm512_fmadd_ps(v, l2, a22);
    v = _mm512_loadu_ps(col[3] + j);
    a30 = _mm512_fmadd_ps(v, l0, a30), a31 = _mm512_fmadd_ps(v, l1, a31);
    a32 = _mm512_fmadd_ps(v, l2, a32);
  }
  const __m512 sums[12] = {a00, a01, a02, a10, a11, a12, a20, a21, a22, a30, a31, a32};
  for (int i = 0; i < 12; ++i) out[i] = _mm512_reduce_add_ps(sums[i]);
  for (int i = 0; i < 4; ++i) dotRgbScalar(col[i], light, j, length, out + 3 * i);
}

ACPCA_AVX512 void dotRgbAvx512(const float* column, const float* const light[3], int length,
                               float out[3]) {
  __m512 r = _mm512_setzero_ps(), g = r, b = r;
  int j = 0;
  for (; j + 16 <= length; j += 16) {
    const __m512 v = _mm512_loadu_ps(column + j);
    r = _mm512_fmadd_ps(v, _mm512_loadu_ps(light[0] + j), r);
    g = _mm512_fmadd_ps(v, _mm512_loadu_ps(light[1] + j), g);
    b = _mm512_fmadd_ps(v, _mm512_loadu_ps(light[2] + j), b);
  }
  out[0] = _mm512_reduce_add_ps(r), out[1] = _mm512_reduce_add_ps(g);
  out[2] = _mm512_reduce_add_ps(b);
  dotRgbScalar(column, light, j, length, out);
}

template <typename T>
ACPCA_AVX512 void shadeChunkOneAvx512(const T* coefficients, const float* transport, int rank,
                                      float base, float out[kChunkRows]) {
  // Four accumulators (k mod 4) cover the FMA latency.
  __m512 a0 = _mm512_set1_ps(base), a1 = _mm512_setzero_ps(), a2 = a1, a3 = a1;
  int k = 0;
  for (; k + 4 <= rank; k += 4) {
    const T* u = coefficients + k * kChunkRows;
    a0 = _mm512_fmadd_ps(load16(u), _mm512_set1_ps(transport[k]), a0);
    a1 = _mm512_fmadd_ps(load16(u + kChunkRows), _mm512_set1_ps(transport[k + 1]), a1);
    a2 = _mm512_fmadd_ps(load16(u + 2 * kChunkRows), _mm512_set1_ps(transport[k + 2]), a2);
    a3 = _mm512_fmadd_ps(load16(u + 3 * kChunkRows), _mm512_set1_ps(transport[k + 3]), a3);
  }
  for (; k < rank; ++k)
    a0 = _mm512_fmadd_ps(load16(coefficients + k * kChunkRows), _mm512_set1_ps(transport[k]), a0);
  _mm512_storeu_ps(out, _mm512_add_ps(_mm512_add_ps(a0, a1), _mm512_add_ps(a2, a3)));
}

ACPCA_AVX512 void dotRgbColumnsAvx512(const float* columns, int count, const float* const light[3],
                                      int length, float* out) {
  int i = 0;
  for (; i + 4 <= count; i += 4)
    dotRgbFourAvx512(columns + static_cast<size_t>(i) * length, light, length, out + 3 * i);
  for (; i < count; ++i)
    dotRgbAvx512(columns + static_cast<size_t>(i) * length, light, length, out + 3 * i);
}

ACPCA_AVX512 void dotSegmentsAvx512(const std::uint16_t* values, const std::uint16_t* segments,
                                    int count, const float* const light[3], float out[3]) {
  __m512 r = _mm512_setzero_ps(), g = r, b = r;
  for (int i = 0; i < count; ++i) {
    const int first = segments[i] * kChunkRows;
    const __m512 v = load16(values + i * kChunkRows);
    r = _mm512_fmadd_ps(v, _mm512_loadu_ps(light[0] + first), r);
    g = _mm512_fmadd_ps(v, _mm512_loadu_ps(light[1] + first), g);
    b = _mm512_fmadd_ps(v, _mm512_loadu_ps(light[2] + first), b);
  }
  out[0] = _mm512_reduce_add_ps(r), out[1] = _mm512_reduce_add_ps(g);
  out[2] = _mm512_reduce_add_ps(b);
}

}  // namespace

const KernelTable* avx512Kernels() {
  static const KernelTable table{dotRgbAvx512,
                                 dotRgbColumnsAvx512,
                                 dotSegmentsAvx512,
                                 shadeChunkAvx512<float>,
                                 shadeChunkAvx512<std::uint16_t>,
                                 shadeChunkAvx512<std::int8_t>,
                                 shadeChunkOneAvx512<float>,
                                 shadeChunkOneAvx512<std::uint16_t>,
                                 shadeChunkOneAvx512<std::int8_t>};
  return &table;
}

}  // namespace acpca::kernels

#else

namespace acpca::kernels {
const KernelTable* avx512Kernels() {
  return nullptr;
}
}  // namespace acpca::kernels

#endif
