#include "relight/relight_kernels.h"

#include <atomic>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "relight/kernels/kernel_table.h"

namespace acpca::kernels {

namespace {

bool cpuHasAvx512() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  return __builtin_cpu_supports("avx512f");
#else
  return false;
#endif
}

const KernelTable* tableFor(Level level) {
  switch (level) {
    case Level::Portable:
      return &portableKernels();
    case Level::Avx2:
      return avx2Kernels();
    case Level::Avx512:
      return cpuHasAvx512() ? avx512Kernels() : nullptr;
  }
  return nullptr;
}

Level initialLevel() {
  const std::vector<Level> levels = supportedLevels();
  if (const char* wanted = std::getenv("ACPCA_KERNELS"); wanted && *wanted)
    for (Level level : levels)
      if (std::string(wanted) == kLevelNames.name(level)) return level;
  return levels.back();
}

struct Active {
  std::atomic<const KernelTable*> table;
  std::atomic<Level> level;
  Active() {
    const Level l = initialLevel();
    level = l;
    table = tableFor(l);
  }
};

Active& active() {
  static Active a;
  return a;
}

const KernelTable& table() {
  return *active().table.load(std::memory_order_relaxed);
}

}  // namespace

std::vector<Level> supportedLevels() {
  std::vector<Level> levels;
  for (Level level : {Level::Portable, Level::Avx2, Level::Avx512})
    if (tableFor(level)) levels.push_back(level);
  return levels;
}

Level activeLevel() {
  return active().level;
}

void useLevel(Level level) {
  const KernelTable* t = tableFor(level);
  if (!t)
    throw UserError(concat(
        "kernels '", kLevelNames.name(level), "': this build or CPU cannot run them (it can: ",
        [] {
          std::string list;
          for (Level l : supportedLevels())
            list += (list.empty() ? "" : ", ") + std::string(kLevelNames.name(l));
          return list;
        }(),
        ")"));
  active().level = level;
  active().table = t;
}

void dotRgbColumns(const float* columns, int count, const float* const light[3], int length,
                   float* out) {
  table().dotRgbColumns(columns, count, light, length, out);
}
void dotSegmentsRgb(const std::uint16_t* values, const std::uint16_t* segments, int count,
                    const float* const light[3], float out[3]) {
  table().dotSegmentsRgb(values, segments, count, light, out);
}
void dotRgb(const float* column, const float* const light[3], int length, float out[3]) {
  table().dotRgb(column, light, length, out);
}
void shadeChunk(const float* u, const float* lighting, int rank, const float base[3],
                float out[3][kChunkRows]) {
  table().shadeF32(u, lighting, rank, base, out);
}
void shadeChunk(const std::uint16_t* u, const float* lighting, int rank, const float base[3],
                float out[3][kChunkRows]) {
  table().shadeF16(u, lighting, rank, base, out);
}
void shadeChunk(const std::int8_t* u, const float* lighting, int rank, const float base[3],
                float out[3][kChunkRows]) {
  table().shadeI8(u, lighting, rank, base, out);
}

void shadeChunkOne(const float* u, const float* transport, int rank, float base,
                   float out[kChunkRows]) {
  table().shadeOneF32(u, transport, rank, base, out);
}
void shadeChunkOne(const std::uint16_t* u, const float* transport, int rank, float base,
                   float out[kChunkRows]) {
  table().shadeOneF16(u, transport, rank, base, out);
}
void shadeChunkOne(const std::int8_t* u, const float* transport, int rank, float base,
                   float out[kChunkRows]) {
  table().shadeOneI8(u, transport, rank, base, out);
}

}  // namespace acpca::kernels
