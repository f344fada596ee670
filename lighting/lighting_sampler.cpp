#include "lighting/lighting_sampler.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace acpca {

std::uint64_t SplitMix64::next() {
  std::uint64_t z = (state_ += kSplitMixIncrement);
  for (const auto& [shift, multiplier] : kSplitMixMixes) z = (z ^ (z >> shift)) * multiplier;
  return z ^ (z >> kSplitMixLastShift);
}

double SplitMix64::uniform() {
  return static_cast<double>(next() >> 11) * 0x1.0p-53;
}

void validateLightingSampling(const LightingSampling& s) {
  if (s.count < 1 || s.count > kMaxLightingSamples)
    throw ParameterError("environment samples", s.count,
                         concat("is not in 1..", kMaxLightingSamples));
  if (!(s.exposureJitter >= 0 && s.exposureJitter <= kMaxExposureJitter))
    throw ParameterError("exposure jitter", s.exposureJitter,
                         concat("is not in 0..", kMaxExposureJitter, " stops"));
}

namespace {

double rounded(double v) {
  return std::round(v * kDrawRoundingSteps) / kDrawRoundingSteps + 0.0;  // + 0.0: no -0 in names
}

LightingDraw nextDraw(SplitMix64& random, const LightingSampling& s, size_t maps) {
  double u[kUniformsPerDraw];
  for (double& v : u) v = random.uniform();
  LightingDraw d;
  d.map = std::min(static_cast<size_t>(u[0] * static_cast<double>(maps)), maps - 1);
  d.rotation.yaw = rounded(360 * u[1]);
  if (s.rotation == SampledRotation::Sphere) {
    d.rotation.pitch = rounded(std::asin(2 * u[2] - 1) * 180 / std::numbers::pi);
    d.rotation.roll = rounded(360 * u[3]);
  }
  d.exposureOffset = rounded(s.exposureJitter * (2 * u[4] - 1));
  return d;
}

}  // namespace

std::vector<LightingDraw> drawLightings(const LightingSampling& s, size_t maps) {
  validateLightingSampling(s);
  ACPCA_CHECK(maps > 0, "no map to draw from");
  SplitMix64 random(s.seed);
  std::vector<LightingDraw> draws(static_cast<size_t>(s.count));
  for (LightingDraw& d : draws) d = nextDraw(random, s, maps);
  return draws;
}

LightingDraw drawLightingAt(const LightingSampling& s, size_t maps, std::uint64_t index) {
  ACPCA_CHECK(maps > 0, "no map to draw from");
  // The state after k outputs is seed + k increments (mod 2^64).
  SplitMix64 random(s.seed + kUniformsPerDraw * index * kSplitMixIncrement);
  return nextDraw(random, s, maps);
}

}  // namespace acpca
