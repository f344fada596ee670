// The 8-bit sRGB encoder the PNG writer and the viewer share: it must give the
// very codes of the formula round(255 * srgb(v * 2^EV)) for every value.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "relight/image_output.h"

namespace acpca {
namespace {

unsigned char formula(float v, double exposureEv) {
  const float scaled = v * static_cast<float>(std::exp2(exposureEv));
  return static_cast<unsigned char>(std::lround(linearToSrgb(scaled) * 255));
}

TEST(SrgbEncoder, GivesTheFormulasCodeForEveryValueTried) {
  for (double ev : {-3.0, 0.0, 1.5, 7.25}) {
    const SrgbEncoder encode(ev);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> logValue(-12, 4);
    for (int i = 0; i < 200000; ++i) {
      const float v = std::exp2(logValue(rng)) * (ev > 0 ? std::exp2(float(-ev)) : 1.0f);
      ASSERT_EQ(encode(v), formula(v, ev)) << "v = " << v << " at EV " << ev;
    }
    // Around every step of the code, one float either side.
    for (int b = 1; b < 256; ++b) {
      float lo = 0, hi = 1;
      for (int k = 0; k < 60; ++k) {
        const float mid = 0.5f * (lo + hi);
        (formula(mid, 0) >= b ? hi : lo) = mid;
      }
      for (float v : {std::nextafter(hi, 0.0f), hi, std::nextafter(hi, 2.0f)})
        EXPECT_EQ(SrgbEncoder(0)(v), formula(v, 0)) << v;
    }
  }
  const SrgbEncoder encode(0);
  EXPECT_EQ(encode(-1.0f), 0);
  EXPECT_EQ(encode(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(encode(1e30f), 255);
  EXPECT_EQ(encode(std::numeric_limits<float>::infinity()), 255);
}

TEST(SrgbEncoder, LeavesAlphaAsCoverage) {
  Image image;
  image.width = 2;
  image.height = 1;
  image.channels = 4;
  image.pixels = {0.5f, 0.25f, 2.0f, 0.5f, 0.0f, 1.0f, 0.01f, 1.0f};
  const auto bytes = SrgbEncoder(1).encode(image);
  EXPECT_EQ(bytes[3], 128);  // alpha 0.5, not tone mapped or scaled
  EXPECT_EQ(bytes[7], 255);
  EXPECT_EQ(bytes[0], formula(0.5f, 1));
  EXPECT_EQ(bytes[6], formula(0.01f, 1));
}

}  // namespace
}  // namespace acpca
