#include "lighting/lighting_sampler.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace acpca {

std::uint64_t SplitMix64::next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double SplitMix64::uniform() {
  return static_cast<double>(next() >> 11) * 0x1.0p-53;
}

void validateLightingSampling(const LightingSampling& s) {
  if (s.count < 1 || s.count > kMaxLightingSamples)
    throw ParameterError("environment samples", s.count,
                         concat("is not in 1..", kMaxLightingSamples));
  if (!(s.exposureJitter >= 0 && s.exposureJitter <= 20))
    throw ParameterError("exposure jitter", s.exposureJitter, "is not in 0..20 stops");
}

namespace {

double rounded(double v) {
  return std::round(v * 1e6) / 1e6 + 0.0;  // + 0.0: no -0 in names
}

}  // namespace

std::vector<LightingDraw> drawLightings(const LightingSampling& s, size_t maps) {
  validateLightingSampling(s);
  ACPCA_CHECK(maps > 0, "no map to draw from");
  SplitMix64 random(s.seed);
  std::vector<LightingDraw> draws(static_cast<size_t>(s.count));
  for (LightingDraw& d : draws) {
    const double u[5] = {random.uniform(), random.uniform(), random.uniform(), random.uniform(),
                         random.uniform()};
    d.map = std::min(static_cast<size_t>(u[0] * static_cast<double>(maps)), maps - 1);
    d.rotation.yaw = rounded(360 * u[1]);
    if (s.rotation == SampledRotation::Sphere) {
      d.rotation.pitch = rounded(std::asin(2 * u[2] - 1) * 180 / std::numbers::pi);
      d.rotation.roll = rounded(360 * u[3]);
    }
    d.exposureOffset = rounded(s.exposureJitter * (2 * u[4] - 1));
  }
  return draws;
}

}  // namespace acpca
