#pragma once
// Counter-based random numbers: a value from a key (a sample's index, a
// stratum), the same whatever thread asks or in what order, so seeded
// estimates write the same bytes every run.
#include <cstdint>

namespace acpca {

/// SplitMix64's finaliser [Steele14]: well-mixed 64 bits from any 64-bit key.
inline std::uint64_t splitMix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// The top 53 bits as a double in [0, 1).
inline double unitFromBits(std::uint64_t x) {
  return double(x >> 11) * 0x1.0p-53;
}

}  // namespace acpca
