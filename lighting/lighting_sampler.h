#pragma once
// Lightings drawn at random, reproducibly: K (map, rotation, exposure) draws
// from a seed, the same on any machine, compiler, thread or rank count (a
// generator of our own, not the standard library's distributions, whose
// algorithms differ between implementations). docs/datasets.md, "Sampled
// lighting".
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "lighting/rotation.h"

namespace acpca {

/// SplitMix64 [Steele14]: 64-bit state, each output a mix of the state after a
/// fixed increment. Fully specified, so every platform draws the same numbers:
/// z = state += kSplitMixIncrement; then for each (shift, multiplier) z = (z ^
/// z >> shift) multiplier; the output z ^ z >> kSplitMixLastShift.
inline constexpr std::uint64_t kSplitMixIncrement = 0x9E3779B97F4A7C15ULL;
inline constexpr std::array<std::pair<int, std::uint64_t>, 2> kSplitMixMixes{
    {{30, 0xBF58476D1CE4E5B9ULL}, {27, 0x94D049BB133111EBULL}}};
inline constexpr int kSplitMixLastShift = 31;

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
/// Widest exposure jitter, in stops.
inline constexpr double kMaxExposureJitter = 20;
/// Uniforms each draw takes (map, yaw, pitch, roll, exposure); its angles and
/// offsets are rounded to 1 / kDrawRoundingSteps: round(v steps) / steps.
inline constexpr int kUniformsPerDraw = 5;
inline constexpr double kDrawRoundingSteps = 1e6;

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
/// Draw `index` of that stream (its count aside), made without the draws
/// before it: what a DataLoader worker making only its own batches needs.
LightingDraw drawLightingAt(const LightingSampling& sampling, size_t maps, std::uint64_t index);

}  // namespace acpca
