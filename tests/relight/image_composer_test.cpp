// Negative colour values of a relit frame (compression's ringing) counted and
// raised to zero, alpha left alone, NaN treated as below zero.
#include "relight/image_composer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace acpca {
namespace {

TEST(ClampNegative, CountsAndRaisesEveryColourValueBelowZero) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> rgb{0.5f, -0.25f, -0.0f, nan, 2.0f, -3.0f, inf, 0.0f, -1e-30f};
  std::vector<float> clamped = rgb;
  const NegativeClamp c = clampNegative(clamped.data(), clamped.size(), 3, false);
  EXPECT_EQ(c.values, 4);  // -0.25, NaN, -3 and -1e-30; -0 is not below zero
  EXPECT_EQ(c.mostNegative, -3.0f);
  const std::vector<float> expected{0.5f, 0.0f, -0.0f, 0.0f, 2.0f, 0.0f, inf, 0.0f, 0.0f};
  for (size_t i = 0; i < rgb.size(); ++i) EXPECT_EQ(clamped[i], expected[i]) << i;
  std::vector<float> kept = rgb;
  const NegativeClamp k = clampNegative(kept.data(), kept.size(), 3, true);
  EXPECT_EQ(k.values, 4);
  EXPECT_EQ(k.mostNegative, -3.0f);
  EXPECT_EQ(kept[5], -3.0f);
  EXPECT_TRUE(std::isnan(kept[3]));
}

TEST(ClampNegative, LeavesAlphaAlone) {
  std::vector<float> rgba{-1.0f, 0.5f, 0.25f, -0.5f, 0.1f, -0.2f, 0.3f, 1.0f};
  const NegativeClamp c = clampNegative(rgba.data(), rgba.size(), 4, false);
  EXPECT_EQ(c.values, 2);
  EXPECT_EQ(c.mostNegative, -1.0f);
  EXPECT_EQ(rgba, (std::vector<float>{0.0f, 0.5f, 0.25f, -0.5f, 0.1f, 0.0f, 0.3f, 1.0f}));
}

}  // namespace
}  // namespace acpca
