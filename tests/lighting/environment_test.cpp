#include "lighting/environment.h"
#include "lighting/latlong_integration.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/error.h"
#include "core/warning.h"
#include "lighting/lighting.h"
#include "lighting/rotation.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;

/// A 2048x1024 black map with one small bright disc; returns its exact energy.
std::unique_ptr<Environment> discMap(const Vec3& centre, double radiusDegrees, double value,
                                     double& energy) {
  const int w = 2048, h = 1024;
  std::vector<float> rgb(3ull * w * h, 0.0f);
  energy = 0;
  const double cosR = std::cos(radiusDegrees * kPi / 180);
  for (int y = 0; y < h; ++y) {
    const double t0 = kPi * y / h, t1 = kPi * (y + 1) / h;
    const double omega = (std::cos(t0) - std::cos(t1)) * 2 * kPi / w;
    for (int x = 0; x < w; ++x) {
      const Vec3 d = directionFromAngles(0.5 * (t0 + t1), 2 * kPi * ((x + 0.5) / w - 0.5));
      if (d.dot(centre.normalized()) < cosR) continue;
      for (int c = 0; c < 3; ++c) rgb[3 * (static_cast<size_t>(y) * w + x) + c] = float(value);
      energy += value * omega;
    }
  }
  return makeLatLongEnvironment("disc", w, h, std::move(rgb));
}

TEST(Environment, ConstantIntegratesToFourPiTimesItsRadiance) {
  const CubeLattice lattice(16);
  const auto env = makeConstantEnvironment(Rgb(1, 2, 3));
  const Rgb e = totalEnergy(computeLighting(*env, lattice, {}));
  EXPECT_NEAR(e[0], 4 * kPi, 1e-9);
  EXPECT_NEAR(e[2], 12 * kPi, 1e-9);
}

TEST(Environment, SunKeepsItsEnergyAtAnySizeAndRotation) {
  for (double size : {0.5, 4.0, 30.0}) {
    const double expected = 7 * 2 * kPi * (1 - std::cos(0.5 * size * kPi / 180));
    const auto sun = makeSunEnvironment(50, 30, size, Rgb::Constant(7));
    for (int r : {8, 32})
      for (const EnvRotation& rot : {EnvRotation{}, EnvRotation{37, 11, -5}}) {
        const Rgb e = totalEnergy(computeLighting(*sun, CubeLattice(r), rot));
        EXPECT_NEAR(e[0] / expected, 1.0, 1e-9) << "size " << size << " R " << r;
      }
  }
}

TEST(Environment, SunSitsWhereItsAnglesSay) {
  const CubeLattice lattice(32);
  const auto sun = makeSunEnvironment(50, 30, 1, Rgb::Constant(1));
  const LatticeLighting L = computeLighting(*sun, lattice, {});
  int brightest = 0;
  for (int j = 0; j < lattice.size(); ++j)
    if (L[3 * j] > L[3 * brightest]) brightest = j;
  const double t = 50 * kPi / 180, p = 30 * kPi / 180;
  const Vec3 expected(std::sin(t) * std::sin(p), std::cos(t), -std::sin(t) * std::cos(p));
  EXPECT_GT(lattice.direction(brightest).dot(expected), std::cos(3 * kPi / 180));
}

TEST(Environment, LatLongDiscKeepsItsEnergyUnrotatedRotatedAndAfterAFullTurn) {
  double energy = 0;
  const auto map = discMap({0.3, 0.8, -0.5}, 0.6, 5000, energy);
  const CubeLattice lattice(32);
  const LatticeLighting plain = computeLighting(*map, lattice, {});
  EXPECT_NEAR(totalEnergy(plain)[0] / energy, 1.0, 0.01);
  const LatticeLighting turned = computeLighting(*map, lattice, {37, 0, 0});
  EXPECT_NEAR(totalEnergy(turned)[0] / energy, 1.0, 0.01);
  const LatticeLighting tilted = computeLighting(*map, lattice, {37, 21, 13});
  EXPECT_NEAR(totalEnergy(tilted)[0] / energy, 1.0, 0.01);
  // 360 degrees is the identity.
  const LatticeLighting full = computeLighting(*map, lattice, {360, 0, 0});
  double diff = 0, norm = 0;
  for (size_t k = 0; k < plain.size(); ++k) {
    diff += (full[k] - plain[k]) * (full[k] - plain[k]);
    norm += plain[k] * plain[k];
  }
  EXPECT_LT(std::sqrt(diff / norm), 1e-6);
}

TEST(Environment, FastLatticeRotationIsMeasurablyWorseOnSmallSuns) {
  // The fast mode of [Nowrouzezahrai07] is offered for interactive use only: it changes
  // the energy of a one-texel sun, where the exact mode keeps it.
  const CubeLattice lattice(32);
  const auto sun = makeSunEnvironment(60, 20, 2.5, Rgb::Constant(100));
  const double energy = totalEnergy(computeLighting(*sun, lattice, {}))[0];
  double worstFast = 0;
  for (double yaw : {13.0, 37.0, 61.0}) {
    const double exact = totalEnergy(computeLighting(*sun, lattice, {yaw, 0, 0}))[0];
    const double fast =
        totalEnergy(computeLighting(*sun, lattice, {yaw, 0, 0}, RotationMode::FastLattice))[0];
    EXPECT_NEAR(exact / energy, 1.0, 1e-9);
    worstFast = std::max(worstFast, std::abs(fast / energy - 1));
  }
  EXPECT_GT(worstFast, 1e-3);
  EXPECT_LT(worstFast, 0.5);
}

TEST(Environment, LatLongTexelsHoldExactlyTheCellsTheRotationSendsThem) {
  // Each sub-cell of a map pixel (radiance x its exact solid angle) belongs to
  // the texel holding its rotated centre: summed here cell by cell, plainly.
  const int w = 256, h = 128;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> value(0, 2);
  std::vector<float> rgb(3 * w * h);
  for (size_t k = 0; k < rgb.size(); ++k) rgb[k] = k % 7 == 0 ? 0.0f : value(rng);
  for (int p = 0; p < 40; ++p) rgb[3 * p] = rgb[3 * p + 1] = rgb[3 * p + 2] = 0;  // black pixels
  const auto map = makeLatLongEnvironment("m", w, h, rgb);
  for (int r : {8, 32}) {
    const CubeLattice lattice(r);
    const int sub = r == 8 ? 1 : 4;  // sub-cells at most 1/8 of a texel across
    // Yaws alone go row by row (latlong_integration.h); the last cell by cell.
    for (const EnvRotation& rot : {EnvRotation{}, EnvRotation{15, 0, 0}, EnvRotation{-170.3, 0, 0},
                                   EnvRotation{90, 0, 0}, EnvRotation{37, 11, -5}}) {
      const Eigen::Matrix3d m = rotationMatrix(rot);
      std::vector<double> expected(3 * lattice.size(), 0.0);
      for (int row = 0; row < h * sub; ++row) {
        const double t0 = kPi * row / (h * sub), t1 = kPi * (row + 1) / (h * sub);
        const double omega = (std::cos(t0) - std::cos(t1)) * 2 * kPi / (w * sub);
        for (int col = 0; col < w * sub; ++col) {
          const Vec3 d =
              directionFromAngles(0.5 * (t0 + t1), 2 * kPi * ((col + 0.5) / (w * sub) - 0.5));
          const int j = lattice.texelOf(m * d);
          for (int c = 0; c < 3; ++c)
            expected[3 * j + c] += omega * rgb[3 * ((row / sub) * w + col / sub) + c];
        }
      }
      LatticeLighting lighting(3 * lattice.size(), 0.0);
      map->integrate(lattice, m, lighting);
      for (size_t k = 0; k < lighting.size(); ++k)
        ASSERT_NEAR(lighting[k], expected[k], 1e-12 * (1 + expected[k]))
            << "R " << r << " yaw " << rot.yaw << " value " << k;
    }
  }
}

TEST(Environment, AYawedMapRowByRowEqualsItCellByCellWithASunInIt) {
  // A map of 1024x512 with a sun 1e5 times the sky, as Blender's world maps
  // are sized, on the 6x32x32 lattice (one sub-cell a pixel) and 6x64x64 (2).
  const int w = 1024, h = 512;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> value(0.1f, 1);
  std::vector<float> rgb(3 * w * h);
  for (float& v : rgb) v = value(rng);
  for (int y = 100; y < 104; ++y)
    for (int x = 300; x < 305; ++x)
      for (int c = 0; c < 3; ++c) rgb[3 * (y * w + x) + c] = 1e5f;
  const auto map = makeLatLongEnvironment("m", w, h, rgb);
  const LatLongPixels& pixels = *map->latLong();
  for (int r : {32, 64}) {
    const CubeLattice lattice(r);
    EXPECT_EQ(latLongSubCells(pixels, lattice), r / 32);
    const LatLongRowSums sums(pixels);
    for (double yaw = -180; yaw <= 180; yaw += 22.5 + 0.01) {
      const Eigen::Matrix3d m = rotationMatrix({yaw, 0, 0});
      ASSERT_TRUE(isYawOnly(m)) << yaw;
      LatticeLighting cells(3 * lattice.size(), 0.0), rows(cells.size(), 0.0);
      integrateLatLongCells(pixels, lattice, m, cells);
      integrateLatLongYawed(pixels, sums, lattice, m, rows);
      for (size_t k = 0; k < cells.size(); ++k)
        ASSERT_NEAR(rows[k], cells[k], 1e-9 * cells[k] + 1e-12) << "R " << r << " yaw " << yaw;
    }
  }
  EXPECT_FALSE(isYawOnly(rotationMatrix({10, 1e-9, 0})));
}

TEST(Environment, YawsMadeTogetherEqualYawsMadeOneByOne) {
  // A 2048x1024 map (past the size integrateMany reads row by row for all
  // yaws at once) and a 1024x512 one (one yaw at a time): every value the
  // same as integrate() gives each rotation alone, also for a rotation that
  // is not a yaw among them.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(0, 1);
  for (auto [w, h] : {std::pair{2048, 1024}, {1024, 512}}) {
    std::vector<float> rgb(3ull * w * h);
    for (float& v : rgb) v = value(rng);
    for (int c = 0; c < 3; ++c) rgb[3 * (300 * w + 700) + c] = 1e5f;  // a sun
    const auto map = makeLatLongEnvironment("m", w, h, rgb);
    const CubeLattice lattice(32);
    std::vector<EnvRotation> rotations;
    for (double yaw = -180; yaw < 180; yaw += 15.5) rotations.push_back({yaw, 0, 0});
    rotations.push_back({});
    for (int pass = 0; pass < 2; ++pass) {
      const std::vector<LatticeLighting> together = computeLightings(*map, lattice, rotations);
      ASSERT_EQ(together.size(), rotations.size());
      for (size_t k = 0; k < rotations.size(); ++k)
        ASSERT_EQ(together[k], computeLighting(*map, lattice, rotations[k]))
            << w << "x" << h << " yaw " << rotations[k].yaw;
      rotations.push_back({10, 20, 0});  // the second pass: not every one a yaw
    }
  }
}

TEST(Environment, LatLongIsReadWithTheDesignOrientation) {
  // A map bright only near u = 0.75 is bright towards +X; near v = 0 at the zenith.
  const int w = 256, h = 128;
  std::vector<float> rgb(3 * w * h, 0.0f);
  for (int y = 60; y < 68; ++y)
    for (int x = 188; x < 196; ++x) rgb[3 * (y * w + x)] = 1;
  const auto map = makeLatLongEnvironment("m", w, h, rgb);
  EXPECT_GT(map->radiance({1, 0, 0})[0], 0.9);
  EXPECT_EQ(map->radiance({-1, 0, 0})[0], 0);
  EXPECT_EQ(map->radiance({0, 0, -1})[0], 0);
}

// Found by fuzz_environment: a damaged header made the loader allocate what it
// declared. Now a map declaring far more pixels than its file could hold is
// refused before the pixel buffer exists.
TEST(Environment, MapsDeclaringMorePixelsThanTheyHoldAreRefusedBeforeReading) {
  test::TempDir dir;
  const std::string path = dir.file("big.exr");
  std::vector<float> pixels(3 * 2048 * 1024, 0.25f);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out->open(path, OIIO::ImageSpec(2048, 1024, 3, OIIO::TypeDesc::FLOAT)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  out->close();
  EXPECT_NO_THROW(loadEnvironmentImage(path));  // whole, it reads
  test::fs::resize_file(path, 3000);
  try {
    loadEnvironmentImage(path);
    FAIL() << "a map cut to 3000 bytes was read";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("big.exr"), std::string::npos) << e.what();
  }
}

/// A 16x8 float EXR of 0.5 everywhere with `changes` applied (value index, value).
std::string writeSmallMap(const test::TempDir& dir, const std::string& name,
                          const std::vector<std::pair<int, float>>& changes) {
  const std::string path = dir.file(name);
  std::vector<float> pixels(3 * 16 * 8, 0.5f);
  for (const auto& [index, value] : changes) pixels[index] = value;
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out->open(path, OIIO::ImageSpec(16, 8, 3, OIIO::TypeDesc::FLOAT)));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  out->close();
  return path;
}

TEST(Environment, FilesWithNaNOrInfTexelsAreRefusedNamingThePixel) {
  test::TempDir dir;
  for (float bad : {NAN, INFINITY, -INFINITY}) {
    const std::string path = writeSmallMap(dir, "bad.exr", {{3 * 20 + 1, bad}});
    try {
      loadEnvironment(path);
      FAIL() << "accepted a texel of " << bad;
    } catch (const UserError& e) {
      EXPECT_NE(std::string(e.what()).find("(4, 1)"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.exr"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(loadEnvironment(dir.file("missing.exr")), UserError);
}

TEST(Environment, AFullSizeMapNamesItsFirstNonFiniteTexelInReadingOrder) {
  // 2048x1024, its rows checked on all cores: the first bad texel in reading
  // order is named whichever row is checked first, and a -Inf beside
  // negative texels is named, not clamped.
  const int w = 2048, h = 1024;
  std::vector<float> pixels(3ull * w * h, 0.25f);
  const auto at = [&](int x, int y, int c) -> float& {
    return pixels[3 * (size_t(y) * w + x) + c];
  };
  at(9, 900, 0) = NAN;
  at(1500, 301, 1) = -1e-6f;
  at(1501, 301, 2) = -INFINITY;
  at(2047, 700, 0) = INFINITY;
  try {
    makeEnvironmentFromPixels("big", "big", w, h, 3, pixels.data());
    FAIL() << "accepted a map with NaN and Inf";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("pixel (1501, 301) channel 2 is -inf"), std::string::npos)
        << e.what();
  }
}

TEST(Environment, AGreyMapIsReadAsEqualRgb) {
  std::vector<float> grey(16 * 8);
  for (size_t i = 0; i < grey.size(); ++i) grey[i] = 0.1f * i;
  std::vector<float> rgb;
  for (float g : grey) rgb.insert(rgb.end(), {g, g, g});
  const CubeLattice lattice(4);
  EXPECT_EQ(
      computeLighting(*makeEnvironmentFromPixels("g", "g", 16, 8, 1, grey.data()), lattice, {}),
      computeLighting(*makeEnvironmentFromPixels("c", "c", 16, 8, 3, rgb.data()), lattice, {}));
}

TEST(Environment, TinyNegativeTexelsAreClampedWithOneWarning) {
  test::TempDir dir;
  // Ringing as filtered HDRIs have it: a few values just below zero.
  const std::string ringing =
      writeSmallMap(dir, "ringing.exr", {{5, -4.5e-6f}, {100, -0.004f}, {201, -1e-7f}});
  const std::string clean = writeSmallMap(dir, "clean.exr", {{5, 0}, {100, 0}, {201, 0}});
  std::vector<std::string> warnings;
  const WarningHandler previous =
      setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
  const auto env = loadEnvironment(ringing);
  setWarningHandler(previous);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("3 negative values clamped to 0"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("-0.004"), std::string::npos) << warnings[0];
  // Clamped means exactly the map with zeros there.
  const CubeLattice lattice(4);
  EXPECT_EQ(computeLighting(*env, lattice, {}),
            computeLighting(*loadEnvironment(clean), lattice, {}));
}

TEST(Environment, NegativeTexelsBelowAMillionthOfTheMapAreClampedSilently) {
  test::TempDir dir;
  // The stock maps' case: a few values far below a millionth of the magnitude.
  const std::string ringing = writeSmallMap(dir, "faint.exr", {{5, -1e-8f}, {201, -2e-8f}});
  const std::string clean = writeSmallMap(dir, "clean.exr", {{5, 0}, {201, 0}});
  std::vector<std::string> warnings;
  const WarningHandler previous =
      setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
  const auto env = loadEnvironment(ringing);
  setWarningHandler(previous);
  EXPECT_TRUE(warnings.empty()) << (warnings.empty() ? "" : warnings[0]);
  const CubeLattice lattice(4);
  EXPECT_EQ(computeLighting(*env, lattice, {}),
            computeLighting(*loadEnvironment(clean), lattice, {}));
}

TEST(Environment, MapsWhoseNegativeValuesHoldRealEnergyAreRefused) {
  test::TempDir dir;
  std::vector<std::pair<int, float>> changes;
  for (int i = 0; i < 40; ++i) changes.push_back({3 * i, -0.5f});  // 40 of 384 values
  const std::string path = writeSmallMap(dir, "broken.exr", changes);
  try {
    loadEnvironment(path);
    FAIL() << "accepted a map with 10% negative magnitude";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.exr: 40 negative values"), std::string::npos)
        << e.what();
  }
}

TEST(Environment, SpecsParseOrFailClearly) {
  EXPECT_EQ(loadEnvironment("constant:2")->name(), "constant_2");
  EXPECT_EQ(loadEnvironment("sun:50,30,4,1000")->name(), "sun_50_30_4_1000");
  EXPECT_EQ(loadEnvironment("sky")->name(), "sky");
  for (const char* bad : {"constant:", "constant:-1", "constant:x", "sun:1,2,3", "sun:1,2,0,5",
                          "sun:1,2,3,-5", "sun:1,2,3,nan"})
    EXPECT_THROW(loadEnvironment(bad), UserError) << bad;
}

TEST(Rotation, SpecsAndConventions) {
  EXPECT_EQ(parseRotationSpec("0:360:15").size(), 24u);
  const auto r = parseRotationSpec("10,20,30");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].roll, 30);
  EXPECT_EQ(r[0].label(), "y10_p20_r30");
  for (const char* bad : {"", "a", "1,2", "10:0:5", "0:10:0", "0:10", "1,,2"})
    EXPECT_THROW(parseRotationSpec(bad), UserError) << bad;
  // Positive yaw turns +X towards -Z; the order is roll(pitch(yaw(d))).
  EXPECT_TRUE((rotationMatrix({90, 0, 0}) * Vec3(1, 0, 0)).isApprox(Vec3(0, 0, -1), 1e-12));
  EXPECT_TRUE(rotationMatrix({360, 0, 0}).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  const Eigen::Matrix3d m = rotationMatrix({30, 40, 50});
  EXPECT_TRUE(m.isApprox(
      rotationMatrix({0, 0, 50}) * rotationMatrix({0, 40, 0}) * rotationMatrix({30, 0, 0}), 1e-12));
}

}  // namespace
}  // namespace acpca
