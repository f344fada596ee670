// Ng 2003's wavelet baseline: the 2D Haar transform is orthonormal and
// invertible, and the sparse wavelet-domain relight is the dense relight when
// nothing is dropped.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

#include "eval/error_measures.h"
#include "eval/haar_transport.h"
#include "lighting/lighting.h"
#include "relight/dense_relight.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

TEST(Haar2d, IsOrthonormalAndInvertible) {
  for (int r : {1, 2, 8, 32}) {
    std::mt19937 rng(r);
    std::normal_distribution<float> gauss;
    std::vector<float> face(r * r);
    for (auto& v : face) v = gauss(rng);
    const std::vector<float> original = face;
    haarForward2d(face.data(), r);
    double before = 0, after = 0;
    for (int i = 0; i < r * r; ++i) {
      before += double(original[i]) * original[i];
      after += double(face[i]) * face[i];
    }
    EXPECT_NEAR(after, before, 1e-5 * before) << "Parseval at R = " << r;
    haarInverse2d(face.data(), r);
    for (int i = 0; i < r * r; ++i) EXPECT_NEAR(face[i], original[i], 1e-5f);
  }
  // A constant face has one non-zero coefficient: the scaling function, R times the value.
  std::vector<float> flat(64, 2.0f);
  haarForward2d(flat.data(), 8);
  EXPECT_NEAR(flat[0], 16.0f, 1e-5f);
  for (int i = 1; i < 64; ++i) EXPECT_NEAR(flat[i], 0.0f, 1e-6f);
}

TEST(HaarTransport, KeepingEveryTermIsTheDenseRelight) {
  // One row per pixel, and R, G and B rows side by side (the bounced plant).
  for (const char* name : {"small-plant", "bounced-plant"}) {
    const TransportReader transport(test::fixture(name));
    const CubeLattice lattice(transport.header().cubemapResolution);
    const std::vector<LatticeLighting> lightings = {
        computeLighting(*loadEnvironment("sky"), lattice, {}),
        computeLighting(*loadEnvironment("sun:50,30,8,1000"), lattice, {})};
    const auto truth = denseRelight(transport, lightings);
    HaarTransport exact(transport, 0), dropped(transport, 6);
    EXPECT_LE(dropped.fillRatio(), exact.fillRatio());
    EXPECT_GT(exact.fillRatio(), 0.0);
    for (size_t k = 0; k < lightings.size(); ++k) {
      // Half-precision wavelet values: about 2^-11 relative per term.
      EXPECT_LT(relativeL2(exact.relight(lightings[k], transport.latticeSize()), truth[k]), 2e-3)
          << name;
      EXPECT_NEAR(exact.lastCostPerPixel(), exact.fillRatio() * transport.latticeSize(), 1e-6);
      // No terms: black; a few terms: an approximation, worse than all of them.
      for (float v : exact.relight(lightings[k], 0)) ASSERT_EQ(v, 0.0f);
      EXPECT_EQ(exact.lastCostPerPixel(), 0.0);
      const double few = relativeL2(exact.relight(lightings[k], 4), truth[k]);
      EXPECT_GT(few, 1e-2) << name;
      EXPECT_LT(few, 1.0) << name;
    }
  }
}

}  // namespace
}  // namespace acpca
