#include "relight/dense_relight.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "lighting/lighting.h"
#include "lighting/rotation.h"
#include "relight/image_composer.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

class DenseRelight : public ::testing::Test {
 protected:
  // The grid2d scene at 40x30 on a 6x8x8 lattice, made by the build.
  std::string path_ = test::fixture("grid2d");
};

TEST_F(DenseRelight, EqualsAPlainLoopOverTheFile) {
  const TransportReader t(path_);
  const CubeLattice lattice(8);
  const LatticeLighting L = computeLighting(*loadEnvironment("sky"), lattice, {25, 0, 0});
  const auto result = denseRelight(t, {L});
  std::vector<float> rows(t.rows() * t.latticeSize());
  t.readRows(0, t.rows(), rows.data());
  for (long long r = 0; r < t.rows(); ++r)
    for (int c = 0; c < 3; ++c) {
      double dot = 0;
      for (int j = 0; j < t.latticeSize(); ++j)
        dot += double(rows[r * t.latticeSize() + j]) * L[3 * j + c];
      const double expected = t.header().albedo[3 * r + c] * dot;
      ASSERT_NEAR(result[0][3 * r + c], expected, 1e-5 * (1 + std::abs(expected)));
    }
}

TEST_F(DenseRelight, ManyMapsAtOnceEqualOneAtATimeForAnyThreadCount) {
  const TransportReader t(path_);
  const CubeLattice lattice(8);
  std::vector<LatticeLighting> lightings;
  for (const char* env : {"sky", "constant:1", "sun:30,60,5,400"})
    lightings.push_back(computeLighting(*loadEnvironment(env), lattice, {}));
  const auto together = denseRelight(t, lightings);
  for (size_t m = 0; m < lightings.size(); ++m) {
    const auto alone = denseRelight(t, {lightings[m]});
    for (size_t k = 0; k < alone[0].size(); ++k)
      ASSERT_NEAR(together[m][k], alone[0][k], 1e-6 * (1 + std::abs(alone[0][k])));
  }
  std::vector<std::vector<float>> single;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    single = denseRelight(t, lightings);
  }
  EXPECT_EQ(single, together);
}

TEST_F(DenseRelight, ComposedImagesShowBackgroundAsAsked) {
  const TransportReader t(path_);
  const CubeLattice lattice(8);
  const auto env = loadEnvironment("constant:0.25");
  const auto result = denseRelight(t, {computeLighting(*env, lattice, {})});
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  const Image withEnv = composeImage(t.header(), result[0], Background::Env, *env, identity);
  const Image black = composeImage(t.header(), result[0], Background::Black, *env, identity);
  const Image alpha = composeImage(t.header(), result[0], Background::Alpha, *env, identity);
  ASSERT_EQ(alpha.channels, 4);
  int background = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      if (test::rowOfPixel(t.header(), x, y) >= 0) continue;
      ++background;
      EXPECT_FLOAT_EQ(withEnv.at(x, y)[0], 0.25f);
      EXPECT_EQ(black.at(x, y)[0], 0.0f);
      EXPECT_EQ(alpha.at(x, y)[3], 0.0f);
    }
  EXPECT_GT(background, 0) << "the test scene should show some sky";
  for (const float v : withEnv.pixels) EXPECT_TRUE(std::isfinite(v));
}

TEST_F(DenseRelight, AMapTurnedByAYawAloneShowsWhatItsRadianceSays) {
  // The background of a lat-long map under a yaw alone slides along u from a
  // table made once (relight/image_composer.h); under any rotation it must
  // show env.radiance(R^T ray) for each background pixel's camera ray.
  const TransportReader t(path_);
  const TransportHeader& h = t.header();
  const int w = 64, height = 32;
  std::vector<float> rgb(3 * w * height);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<float>((i * 7919 % 1000) / 250.0);
  const auto env = makeLatLongEnvironment("noise", w, height, rgb);
  const std::vector<float> rows(3 * static_cast<size_t>(t.rows()), 0.0f);
  int background = 0;
  for (const EnvRotation& r :
       {EnvRotation{0, 0, 0}, EnvRotation{37.5, 0, 0}, EnvRotation{-170, 0, 0},
        EnvRotation{200, 0, 0}, EnvRotation{30, 10, 0}, EnvRotation{30, 0, 5}}) {
    const Eigen::Matrix3d rotation = rotationMatrix(r);
    const Image image = composeImage(h, rows, Background::Env, *env, rotation);
    for (int y = 0; y < h.camera.size.height; ++y)
      for (int x = 0; x < h.camera.size.width; ++x) {
        if (test::rowOfPixel(h, x, y) >= 0) continue;
        ++background;
        const Rgb expected =
            env->radiance(rotation.transpose() * h.camera.rayDirection(x + 0.5, y + 0.5));
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(image.at(x, y)[c], expected[c], 1e-6 * (1 + expected[c]))
              << "yaw " << r.yaw << " pixel " << x << "," << y;
      }
  }
  EXPECT_GT(background, 6 * 10);
}

}  // namespace
}  // namespace acpca
