#pragma once
// The inner loops of the model relighter, one per stored element type (float,
// IEEE half as uint16, int8). They are memory-bound streams: each reads its
// input once, in order, and sums in a fixed order so that results do not depend
// on how work is split between threads. Each exists at three instruction-set
// levels (kernels/), the best the CPU runs chosen at start-up.
#include <cstdint>
#include <vector>

#include "core/enum_names.h"

namespace acpca::kernels {

enum class Level { Portable, Avx2, Avx512 };
inline constexpr EnumNames<Level, 3> kLevelNames{
    "kernels", {{{Level::Portable, "portable"}, {Level::Avx2, "avx2"}, {Level::Avx512, "avx512"}}}};

/// The levels this build and CPU can run, lowest first.
std::vector<Level> supportedLevels();
/// The level in use: the best supported, or the environment's ACPCA_KERNELS
/// (portable, avx2 or avx512) when it names a supported one.
Level activeLevel();
/// Switches every later call to `level` (comparisons and benchmarks); throws
/// UserError when this build or CPU cannot run it. Not while relighting.
void useLevel(Level level);

/// Rows shaded together: coefficients are stored k-major in chunks of this many
/// rows (one 64-byte line per basis in f32), so one load feeds 16 pixels.
inline constexpr int kChunkRows = 16;

/// out[c] = sum_j column[j] * light[c][j], c = R, G, B: one row of V_g^T L
/// (or a cluster mean's mu_i . L_g).
void dotRgb(const float* column, const float* const light[3], int length, float out[3]);

/// dotRgb of `count` columns stored one after another (stride `length`):
/// out[3 i + c] for column i. Four columns at a time share the loads of light.
void dotRgbColumns(const float* columns, int count, const float* const light[3], int length,
                   float* out);

/// out[c] = sum over the listed 16-texel segments s of sum_lane
/// values[16 i + lane] * light[c][16 s_i + lane]: one row of a transport kept
/// only where it is non-zero.
void dotSegmentsRgb(const std::uint16_t* values, const std::uint16_t* segments, int count,
                    const float* const light[3], float out[3]);

/// out[c][lane] = base[c] + sum_{k < rank} coefficients[k * 16 + lane] * lighting[3k + c]:
/// [Mahajan07] eq. 17 for one chunk of 16 rows of a cluster, and W_i^T L_g for a
/// basis chunk of 16 bases (lanes = bases, k = global index).
void shadeChunk(const float* coefficients, const float* lighting, int rank, const float base[3],
                float out[3][kChunkRows]);
void shadeChunk(const std::uint16_t* coefficients, const float* lighting, int rank,
                const float base[3], float out[3][kChunkRows]);
void shadeChunk(const std::int8_t* coefficients, const float* lighting, int rank,
                const float base[3], float out[3][kChunkRows]);

/// out[lane] = base + sum_{k < rank} coefficients[k * 16 + lane] * transport[k]:
/// one channel of shadeChunk, for 16 rows against one vector (a local light's
/// group transport, relight/local_relight.h).
void shadeChunkOne(const float* coefficients, const float* transport, int rank, float base,
                   float out[kChunkRows]);
void shadeChunkOne(const std::uint16_t* coefficients, const float* transport, int rank, float base,
                   float out[kChunkRows]);
void shadeChunkOne(const std::int8_t* coefficients, const float* transport, int rank, float base,
                   float out[kChunkRows]);

}  // namespace acpca::kernels
