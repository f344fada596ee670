// Sampled lighting: the generator's published outputs, draws that depend on
// the seed alone, and rotations uniform over the sphere.
#include "lighting/lighting_sampler.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include "core/error.h"

namespace acpca {
namespace {

TEST(SplitMix64, GivesTheReferenceOutputsOfSeedZero) {
  // The first outputs of the reference implementation seeded with 0.
  SplitMix64 random(0);
  EXPECT_EQ(random.next(), 0xE220A8397B1DCDAFULL);
  EXPECT_EQ(random.next(), 0x6E789E6AA1B965F4ULL);
  EXPECT_EQ(random.next(), 0x06C45D188009454FULL);
  SplitMix64 uniform(5);
  for (int i = 0; i < 1000; ++i) {
    const double u = uniform.uniform();
    ASSERT_TRUE(u >= 0 && u < 1) << u;
  }
}

TEST(LightingDraws, DependOnTheSeedAloneAndCoverEveryMap) {
  LightingSampling s;
  s.count = 2000;
  s.seed = 42;
  s.exposureJitter = 1.5;
  const std::vector<LightingDraw> a = drawLightings(s, 5), b = drawLightings(s, 5);
  std::vector<int> perMap(5, 0);
  double meanOffset = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].map, b[k].map);
    EXPECT_EQ(a[k].rotation.yaw, b[k].rotation.yaw);
    EXPECT_EQ(a[k].exposureOffset, b[k].exposureOffset);
    ++perMap[a[k].map];
    EXPECT_TRUE(a[k].rotation.yaw >= 0 && a[k].rotation.yaw <= 360);
    EXPECT_EQ(a[k].rotation.pitch, 0);  // yaw alone
    EXPECT_EQ(a[k].rotation.roll, 0);
    EXPECT_LE(std::abs(a[k].exposureOffset), 1.5);
    meanOffset += a[k].exposureOffset / static_cast<double>(a.size());
  }
  for (int n : perMap) EXPECT_NEAR(n, 400, 80);  // 4.5 standard deviations
  EXPECT_NEAR(meanOffset, 0, 0.1);
  // The first draws of a shorter batch are the longer one's.
  s.count = 10;
  EXPECT_EQ(drawLightings(s, 5)[9].rotation.yaw, a[9].rotation.yaw);
  s.seed = 43;
  EXPECT_NE(drawLightings(s, 5)[0].rotation.yaw, a[0].rotation.yaw);
}

TEST(LightingDraws, AnyDrawIsMadeAloneAsTheStreamMakesIt) {
  // Draw k alone, from the state k draws on (seed + 5k increments), is the
  // stream's draw k, whatever the rotation, jitter and seed (2^64 - 1 wraps).
  for (const std::uint64_t seed : {std::uint64_t{0}, std::uint64_t{7}, ~std::uint64_t{0}}) {
    LightingSampling s;
    s.count = 300;
    s.seed = seed;
    s.rotation = SampledRotation::Sphere;
    s.exposureJitter = 2;
    const std::vector<LightingDraw> stream = drawLightings(s, 3);
    for (const size_t k : {size_t{0}, size_t{1}, size_t{150}, size_t{299}}) {
      const LightingDraw alone = drawLightingAt(s, 3, k);
      EXPECT_EQ(alone.map, stream[k].map) << k;
      EXPECT_EQ(alone.rotation.yaw, stream[k].rotation.yaw) << k;
      EXPECT_EQ(alone.rotation.pitch, stream[k].rotation.pitch) << k;
      EXPECT_EQ(alone.rotation.roll, stream[k].rotation.roll) << k;
      EXPECT_EQ(alone.exposureOffset, stream[k].exposureOffset) << k;
    }
  }
}

TEST(LightingDraws, SphereRotationsTurnAnyDirectionUniformlyOverTheSphere) {
  LightingSampling s;
  s.count = 20000;
  s.seed = 3;
  s.rotation = SampledRotation::Sphere;
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0.6, 0, 0.8)}) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    for (const LightingDraw& d : drawLightings(s, 1)) {
      const Eigen::Vector3d w = rotationMatrix(d.rotation) * v;
      mean += w / s.count;
      second += w * w.transpose() / s.count;
    }
    // Uniform on the sphere: mean 0, second moments I / 3 (standard errors
    // 0.004 and 0.002 at 20,000 draws).
    EXPECT_LT(mean.norm(), 0.02) << mean.transpose();
    EXPECT_LT((second - Eigen::Matrix3d::Identity() / 3).cwiseAbs().maxCoeff(), 0.012) << second;
  }
}

TEST(LightingDraws, CountsAndJittersOutOfRangeAreRefusedNamingTheParameter) {
  LightingSampling s;
  for (int count : {0, -3, kMaxLightingSamples + 1}) {
    s.count = count;
    EXPECT_THROW(validateLightingSampling(s), ParameterError) << count;
  }
  s.count = 1;
  for (double jitter : {-1.0, 21.0, std::nan("")}) {
    s.exposureJitter = jitter;
    EXPECT_THROW(validateLightingSampling(s), ParameterError) << jitter;
  }
}

}  // namespace
}  // namespace acpca
