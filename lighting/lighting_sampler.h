#pragma once
// Lightings drawn at random, reproducibly: K (map, rotation, exposure) draws
// from a seed, the same on any machine, compiler, thread or rank count (a
// generator of our own, not the standard library's distributions, whose
// algorithms differ between implementations). docs/datasets.md, "Sampled
// lighting".
#include <cstdint>
#include <vector>

#include "core/enum_names.h"
#include "lighting/rotation.h"

namespace acpca {

/// SplitMix64 [Steele14]: 64-bit state, each output a mix of the state after a
/// fixed increment. Fully specified, so every platform draws the same numbers.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  /// Uniform in [0, 1): the top 53 bits of the next output.
  double uniform();

 private:
  std::uint64_t state_;
};

/// How a drawn map is turned: by yaw alone (the horizon stays level), or by
/// a rotation uniform over all rotations (any direction of the map lands
/// anywhere with equal probability).
enum class SampledRotation { Yaw, Sphere };
inline constexpr EnumNames<SampledRotation, 2> kSampledRotationNames{
    "sampled rotation", {{{SampledRotation::Yaw, "yaw"}, {SampledRotation::Sphere, "sphere"}}}};

struct LightingSampling {
  int count = 0;  ///< K draws; 0: no sampling
  std::uint64_t seed = 0;
  SampledRotation rotation = SampledRotation::Yaw;
  double exposureJitter = 0;  ///< stops: each draw's exposure offset is uniform in +-this
};

/// Most draws one batch takes.
inline constexpr int kMaxLightingSamples = 10'000'000;

struct LightingDraw {
  size_t map = 0;  ///< index into the maps given
  EnvRotation rotation;
  double exposureOffset = 0;  ///< stops, added to the batch's exposure
};

/// Throws ParameterError naming the flag for a count outside 1..kMaxLightingSamples
/// or a jitter that is negative, not finite or above 20 stops.
void validateLightingSampling(const LightingSampling& sampling);

/// The K draws from `maps` maps. Each draw takes five uniforms u in order:
/// map floor(u K), yaw 360 u, pitch asin(2 u - 1) and roll 360 u (sphere:
/// with R = Rz(roll) Rx(pitch) Ry(yaw) that is uniform over rotations; yaw:
/// both 0), exposure offset J (2 u - 1). Angles and offsets are rounded to
/// 10^-6, so the names and manifests they make are short and stable.
std::vector<LightingDraw> drawLightings(const LightingSampling& sampling, size_t maps);

}  // namespace acpca
