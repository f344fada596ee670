// The relighter's loops on AVX2 + FMA + F16C (8 floats a vector), for builds
// that target x86-64-v3.
#include "relight/kernels/kernel_table.h"
#include "relight/kernels/scalar_loops.h"

#if defined(__AVX2__) && defined(__FMA__) && defined(__F16C__)
#include <immintrin.h>

namespace acpca::kernels {

namespace {

inline __m256 load8(const float* p) {
  return _mm256_loadu_ps(p);
}
inline __m256 load8(const std::uint16_t* p) {
  return _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}

inline float horizontalSum(__m256 v) {
  const __m128 s = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  const __m128 t = _mm_add_ps(s, _mm_movehl_ps(s, s));
  return _mm_cvtss_f32(_mm_add_ss(t, _mm_shuffle_ps(t, t, 1)));
}

template <typename T>
void dotRgbAvx2(const T* column, const float* const light[3], int length, float out[3]) {
  // Two accumulators per channel hide the FMA latency.
  __m256 a[2][3] = {};
  int j = 0;
  for (; j + 16 <= length; j += 16)
    for (int h = 0; h < 2; ++h) {
      const __m256 v = load8(column + j + 8 * h);
      for (int c = 0; c < 3; ++c)
        a[h][c] = _mm256_fmadd_ps(v, load8(light[c] + j + 8 * h), a[h][c]);
    }
  for (int c = 0; c < 3; ++c) out[c] = horizontalSum(_mm256_add_ps(a[0][c], a[1][c]));
  dotRgbScalar(column, light, j, length, out);
}

void dotSegmentsAvx2(const std::uint16_t* values, const std::uint16_t* segments, int count,
                     const float* const light[3], float out[3]) {
  __m256 a[2][3] = {};
  for (int i = 0; i < count; ++i) {
    const int base = segments[i] * kChunkRows;
    for (int h = 0; h < 2; ++h) {
      const __m256 v = load8(values + i * kChunkRows + 8 * h);
      for (int c = 0; c < 3; ++c)
        a[h][c] = _mm256_fmadd_ps(v, _mm256_loadu_ps(light[c] + base + 8 * h), a[h][c]);
    }
  }
  for (int c = 0; c < 3; ++c) out[c] = horizontalSum(_mm256_add_ps(a[0][c], a[1][c]));
}

template <typename T>
void dotRgbFourAvx2(const T* columns, const float* const light[3], int length, float* out) {
  __m256 a[4][3] = {};
  int j = 0;
  for (; j + 8 <= length; j += 8) {
    const __m256 l[3] = {_mm256_loadu_ps(light[0] + j), _mm256_loadu_ps(light[1] + j),
                         _mm256_loadu_ps(light[2] + j)};
    for (int i = 0; i < 4; ++i) {
      const __m256 v = load8(columns + static_cast<size_t>(i) * length + j);
      for (int c = 0; c < 3; ++c) a[i][c] = _mm256_fmadd_ps(v, l[c], a[i][c]);
    }
  }
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) out[3 * i + c] = horizontalSum(a[i][c]);
    dotRgbScalar(columns + static_cast<size_t>(i) * length, light, j, length, out + 3 * i);
  }
}

/// Both halves of a chunk's row k, as float.
inline void loadRow(const float* p, __m256& lo, __m256& hi) {
  lo = _mm256_loadu_ps(p);
  hi = _mm256_loadu_ps(p + 8);
}
inline void loadRow(const std::uint16_t* p, __m256& lo, __m256& hi) {
  lo = load8(p);
  hi = load8(p + 8);
}
inline void loadRow(const std::int8_t* p, __m256& lo, __m256& hi) {
  const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  lo = _mm256_cvtepi32_ps(_mm256_cvtepi8_epi32(bytes));
  hi = _mm256_cvtepi32_ps(_mm256_cvtepi8_epi32(_mm_srli_si128(bytes, 8)));
}

template <typename T>
void shadeChunkAvx2(const T* coefficients, const float* lighting, int rank, const float base[3],
                    float out[3][kChunkRows]) {
  // Two sets of accumulators (rows k even and odd) so that each FMA chain waits
  // on its previous FMA only every other step. Named variables, not arrays:
  // GCC keeps arrays of vectors in memory.
  __m256 rLo = _mm256_set1_ps(base[0]), rHi = rLo, gLo = _mm256_set1_ps(base[1]), gHi = gLo,
         bLo = _mm256_set1_ps(base[2]), bHi = bLo;
  __m256 rLo1 = _mm256_setzero_ps(), rHi1 = rLo1, gLo1 = rLo1, gHi1 = rLo1, bLo1 = rLo1,
         bHi1 = rLo1;
  int k = 0;
  for (; k + 2 <= rank; k += 2) {
    const float* l = lighting + 3 * k;
    __m256 uLo, uHi;
    loadRow(coefficients + k * kChunkRows, uLo, uHi);
    __m256 b = _mm256_broadcast_ss(l);
    rLo = _mm256_fmadd_ps(uLo, b, rLo), rHi = _mm256_fmadd_ps(uHi, b, rHi);
    b = _mm256_broadcast_ss(l + 1);
    gLo = _mm256_fmadd_ps(uLo, b, gLo), gHi = _mm256_fmadd_ps(uHi, b, gHi);
    b = _mm256_broadcast_ss(l + 2);
    bLo = _mm256_fmadd_ps(uLo, b, bLo), bHi = _mm256_fmadd_ps(uHi, b, bHi);
    loadRow(coefficients + (k + 1) * kChunkRows, uLo, uHi);
    b = _mm256_broadcast_ss(l + 3);
    rLo1 = _mm256_fmadd_ps(uLo, b, rLo1), rHi1 = _mm256_fmadd_ps(uHi, b, rHi1);
    b = _mm256_broadcast_ss(l + 4);
    gLo1 = _mm256_fmadd_ps(uLo, b, gLo1), gHi1 = _mm256_fmadd_ps(uHi, b, gHi1);
    b = _mm256_broadcast_ss(l + 5);
    bLo1 = _mm256_fmadd_ps(uLo, b, bLo1), bHi1 = _mm256_fmadd_ps(uHi, b, bHi1);
  }
  if (k < rank) {
    const float* l = lighting + 3 * k;
    __m256 uLo, uHi;
    loadRow(coefficients + k * kChunkRows, uLo, uHi);
    rLo = _mm256_fmadd_ps(uLo, _mm256_broadcast_ss(l), rLo);
    rHi = _mm256_fmadd_ps(uHi, _mm256_broadcast_ss(l), rHi);
    gLo = _mm256_fmadd_ps(uLo, _mm256_broadcast_ss(l + 1), gLo);
    gHi = _mm256_fmadd_ps(uHi, _mm256_broadcast_ss(l + 1), gHi);
    bLo = _mm256_fmadd_ps(uLo, _mm256_broadcast_ss(l + 2), bLo);
    bHi = _mm256_fmadd_ps(uHi, _mm256_broadcast_ss(l + 2), bHi);
  }
  _mm256_storeu_ps(out[0], _mm256_add_ps(rLo, rLo1));
  _mm256_storeu_ps(out[0] + 8, _mm256_add_ps(rHi, rHi1));
  _mm256_storeu_ps(out[1], _mm256_add_ps(gLo, gLo1));
  _mm256_storeu_ps(out[1] + 8, _mm256_add_ps(gHi, gHi1));
  _mm256_storeu_ps(out[2], _mm256_add_ps(bLo, bLo1));
  _mm256_storeu_ps(out[2] + 8, _mm256_add_ps(bHi, bHi1));
}

template <typename T>
void shadeChunkOneAvx2(const T* coefficients, const float* transport, int rank, float base,
                       float out[kChunkRows]) {
  // Four accumulator pairs (k mod 4): independent FMA chains cover the latency.
  __m256 lo0 = _mm256_set1_ps(base), hi0 = lo0;
  __m256 lo1 = _mm256_setzero_ps(), hi1 = lo1, lo2 = lo1, hi2 = lo1, lo3 = lo1, hi3 = lo1;
  int k = 0;
  __m256 uLo, uHi;
  for (; k + 4 <= rank; k += 4) {
    const T* u = coefficients + k * kChunkRows;
    loadRow(u, uLo, uHi);
    __m256 t = _mm256_broadcast_ss(transport + k);
    lo0 = _mm256_fmadd_ps(uLo, t, lo0), hi0 = _mm256_fmadd_ps(uHi, t, hi0);
    loadRow(u + kChunkRows, uLo, uHi);
    t = _mm256_broadcast_ss(transport + k + 1);
    lo1 = _mm256_fmadd_ps(uLo, t, lo1), hi1 = _mm256_fmadd_ps(uHi, t, hi1);
    loadRow(u + 2 * kChunkRows, uLo, uHi);
    t = _mm256_broadcast_ss(transport + k + 2);
    lo2 = _mm256_fmadd_ps(uLo, t, lo2), hi2 = _mm256_fmadd_ps(uHi, t, hi2);
    loadRow(u + 3 * kChunkRows, uLo, uHi);
    t = _mm256_broadcast_ss(transport + k + 3);
    lo3 = _mm256_fmadd_ps(uLo, t, lo3), hi3 = _mm256_fmadd_ps(uHi, t, hi3);
  }
  for (; k < rank; ++k) {
    loadRow(coefficients + k * kChunkRows, uLo, uHi);
    const __m256 t = _mm256_broadcast_ss(transport + k);
    lo0 = _mm256_fmadd_ps(uLo, t, lo0), hi0 = _mm256_fmadd_ps(uHi, t, hi0);
  }
  _mm256_storeu_ps(out, _mm256_add_ps(_mm256_add_ps(lo0, lo1), _mm256_add_ps(lo2, lo3)));
  _mm256_storeu_ps(out + 8, _mm256_add_ps(_mm256_add_ps(hi0, hi1), _mm256_add_ps(hi2, hi3)));
}

void dotRgbColumnsAvx2(const float* columns, int count, const float* const light[3], int length,
                       float* out) {
  int i = 0;
  for (; i + 4 <= count; i += 4)
    dotRgbFourAvx2(columns + static_cast<size_t>(i) * length, light, length, out + 3 * i);
  for (; i < count; ++i)
    dotRgbAvx2(columns + static_cast<size_t>(i) * length, light, length, out + 3 * i);
}

}  // namespace

const KernelTable* avx2Kernels() {
  static const KernelTable table{dotRgbAvx2<float>,
                                 dotRgbColumnsAvx2,
                                 dotSegmentsAvx2,
                                 shadeChunkAvx2<float>,
                                 shadeChunkAvx2<std::uint16_t>,
                                 shadeChunkAvx2<std::int8_t>,
                                 shadeChunkOneAvx2<float>,
                                 shadeChunkOneAvx2<std::uint16_t>,
                                 shadeChunkOneAvx2<std::int8_t>};
  return &table;
}

}  // namespace acpca::kernels

#else

namespace acpca::kernels {
const KernelTable* avx2Kernels() {
  return nullptr;
}
}  // namespace acpca::kernels

#endif
