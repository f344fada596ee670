// A map's compact bright sources (lighting/map_sources.h): found where they
// are, split off with the map's energy kept to rounding, across the seam and
// at a pole, at most K of them, none wider than the limit, and `--sun`'s
// values parsed or refused.
#include "lighting/map_sources.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "lighting/sh_lighting.h"

namespace acpca {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180;

/// A direction THETA degrees from +Y at azimuth PHI (0 towards -Z, 90 towards +X).
Vec3 direction(double theta, double phi) {
  theta *= kDegree, phi *= kDegree;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

struct TestMap {
  int width, height;
  std::vector<float> rgb;
  TestMap(int w, int h) : width(w), height(h), rgb(3ull * w * h) {}
  LatLongPixels pixels() const { return {width, height, rgb.data()}; }
  /// A smooth sky, brighter towards +Y.
  void sky(double scale = 1) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const double up = latLongPixelDirection(x, y, width, height)[1];
        float* p = &rgb[3 * (size_t(y) * width + x)];
        p[0] = float(scale * (0.4 + 0.3 * up)), p[1] = float(scale * (0.5 + 0.3 * up)),
        p[2] = float(scale * (0.8 + 0.4 * up));
      }
  }
  /// Pixels whose centres lie within `radius` degrees of `d` set to `value`.
  int disc(const Vec3& d, double radius, const Rgb& value) {
    int set = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        if (latLongPixelDirection(x, y, width, height).dot(d) >= std::cos(radius * kDegree)) {
          for (int c = 0; c < 3; ++c) rgb[3 * (size_t(y) * width + x) + c] = float(value[c]);
          ++set;
        }
    return set;
  }
};

/// Sum of radiance x solid angle over a map's pixels.
Rgb mapEnergy(const LatLongPixels& m) {
  Rgb sum = Rgb::Zero();
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x)
      for (int c = 0; c < 3; ++c)
        sum[c] +=
            latLongPixelSolidAngle(y, m.width, m.height) * m.rgb[3 * (size_t(y) * m.width + x) + c];
  return sum;
}

void expectEnergyKept(const TestMap& map, const SplitMap& split) {
  Rgb total = mapEnergy(split.pixels());
  for (const MapSource& s : split.sources) total += s.energy();
  const Rgb before = mapEnergy(map.pixels());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(total[c], before[c], 1e-9 * before[c]) << c;
}

double angleDegrees(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) / kDegree;
}

TEST(MapSources, PixelSolidAnglesSumToTheSphere) {
  double sum = 0;
  for (int y = 0; y < 37; ++y) sum += 74 * latLongPixelSolidAngle(y, 74, 37);
  EXPECT_NEAR(sum, 4 * kPi, 1e-12);
}

double luminance(const Rgb& c) {
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

TEST(MapSources, AClearDaysSunIsFoundWhereItIsWithTheMapsEnergyKept) {
  // A 0.53-degree sun of radiance 4e4 over a dim sky: 8 in 10 of the light.
  TestMap map(2048, 1024), skyAlone(2048, 1024);
  map.sky(0.09), skyAlone.sky(0.09);
  const Vec3 sun = direction(50, 30);
  ASSERT_GT(map.disc(sun, 0.265, Rgb(4e4, 4e4, 4e4)), 3);
  const SplitMap split = splitMapSources(map.pixels(), SourceFinding{});
  ASSERT_EQ(split.sources.size(), 1u);
  const MapSource& s = split.sources[0];
  EXPECT_LT(angleDegrees(s.direction, sun), 0.05);
  const double whole = luminance(mapEnergy(map.pixels()));
  const double share = (whole - luminance(mapEnergy(skyAlone.pixels()))) / whole;
  EXPECT_GT(share, 0.75);
  EXPECT_NEAR(s.energyShare, share, 1e-4) << "the sky under the sun stays in the map";
  EXPECT_NEAR(s.radius / kDegree, 0.3, 0.1);
  expectEnergyKept(map, split);
  // The sun's pixels now hold the sky about them.
  const SplitMap again = splitMapSources(split.pixels(), SourceFinding{});
  EXPECT_TRUE(again.sources.empty());
}

TEST(MapSources, ASourceAcrossTheSeamOrAtAPoleIsOneSource) {
  for (const Vec3& d : {direction(80, 180), direction(0.05, 0), direction(179.9, 77)}) {
    TestMap map(512, 256);
    map.sky();
    map.disc(d, 1.5, Rgb(5e3, 4e3, 3e3));
    const SplitMap split = splitMapSources(map.pixels(), SourceFinding{});
    ASSERT_EQ(split.sources.size(), 1u) << d.transpose();
    EXPECT_LT(angleDegrees(split.sources[0].direction, d), 0.5) << d.transpose();
    expectEnergyKept(map, split);
  }
}

TEST(MapSources, AtMostKSourcesTheBrightestAndTheRestStayInTheMap) {
  TestMap map(512, 256);
  map.sky();
  for (int k = 0; k < 6; ++k)
    map.disc(direction(40 + 15 * k, 60 * k), 1.5, Rgb::Constant(1e3 * (k + 1)));
  SourceFinding four;
  four.maxSources = 4;
  const SplitMap split = splitMapSources(map.pixels(), four);
  ASSERT_EQ(split.sources.size(), 4u);
  for (int k = 0; k < 4; ++k)  // brightest first: lamps 5, 4, 3, 2
    EXPECT_LT(angleDegrees(split.sources[k].direction, direction(40 + 15 * (5 - k), 60 * (5 - k))),
              0.5);
  // Lamps 0 and 1 are untouched.
  for (int k = 0; k < 2; ++k) {
    const Vec3 d = direction(40 + 15 * k, 60 * k);
    const double u = 0.5 + std::atan2(d[0], -d[2]) / (2 * kPi), v = std::acos(d[1]) / kPi;
    const size_t p = size_t(v * 256) * 512 + size_t(u * 512);
    EXPECT_EQ(split.residual[3 * p], map.rgb[3 * p]) << k;
  }
  expectEnergyKept(map, split);
}

TEST(MapSources, AWideBrightRegionOrAUniformMapIsNoSource) {
  TestMap map(256, 128);
  map.sky();
  map.disc(direction(30, 0), 10, Rgb::Constant(1e4));  // ten degrees: a softbox, not a sun
  const SplitMap wide = splitMapSources(map.pixels(), SourceFinding{});
  EXPECT_TRUE(wide.sources.empty());
  EXPECT_EQ(wide.residual, map.rgb);
  TestMap flat(64, 32);
  std::fill(flat.rgb.begin(), flat.rgb.end(), 2.f);
  EXPECT_TRUE(splitMapSources(flat.pixels(), SourceFinding{}).sources.empty());
  TestMap black(64, 32);
  EXPECT_TRUE(splitMapSources(black.pixels(), SourceFinding{}).sources.empty());
}

TEST(MapSources, AMapThatIsAlmostAllOneBrightPixelIsThatSource) {
  TestMap map(256, 128);
  std::fill(map.rgb.begin(), map.rgb.end(), 1e-4f);
  const size_t p = 40 * 256 + 100;
  for (int c = 0; c < 3; ++c) map.rgb[3 * p + c] = 1e6f;
  const SplitMap split = splitMapSources(map.pixels(), SourceFinding{});
  ASSERT_EQ(split.sources.size(), 1u);
  EXPECT_GT(split.sources[0].energyShare, 0.999);
  EXPECT_LT(angleDegrees(split.sources[0].direction, latLongPixelDirection(100, 40, 256, 128)),
            1e-9);
  EXPECT_EQ(split.residual[3 * p], 1e-4f);  // the dim pixels about it
  expectEnergyKept(map, split);
}

/// Each channel's sum of a lighting over the lattice: its energy.
Rgb latticeEnergy(const Environment& env, const CubeLattice& lattice) {
  LatticeLighting l(3 * static_cast<size_t>(lattice.size()), 0.0);
  env.integrate(lattice, Eigen::Matrix3d::Identity(), l);
  Rgb sum = Rgb::Zero();
  for (int j = 0; j < lattice.size(); ++j) sum += Rgb(l[3 * j], l[3 * j + 1], l[3 * j + 2]);
  return sum;
}

TEST(MapSources, TheBuiltInSunAndTheSkysSunSplitOffWithTheirEnergy) {
  // `sun:` is all source, the sky keeps its sky: source plus rest hold the
  // map's energy on the lattice; a disc wider than the limit stays.
  const CubeLattice lattice(16);
  for (const char* spec : {"sun:50,30,0.53,40000", "sky"}) {
    const auto env = loadEnvironment(spec);
    const SplitEnvironment split = env->splitSources(SourceFinding{});
    ASSERT_EQ(split.sources.size(), 1u) << spec;
    ASSERT_TRUE(split.rest) << spec;
    const Rgb whole = latticeEnergy(*env, lattice);
    const Rgb parts = latticeEnergy(*split.rest, lattice) + split.sources[0].energy();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(parts[c] / whole[c], 1, 1e-9) << spec;
    EXPECT_GT(split.sources[0].energyShare, 0.3) << spec;
    EXPECT_LE(split.sources[0].energyShare, 1) << spec;
  }
  const MapSource sun = loadEnvironment("sun:50,30,0.53,40000")->splitSources({}).sources[0];
  EXPECT_NEAR(sun.thetaDegrees(), 50, 1e-9);
  EXPECT_NEAR(sun.phiDegrees(), 30, 1e-9);
  EXPECT_NEAR(sun.radius / kDegree, 0.265, 1e-12);
  EXPECT_TRUE(loadEnvironment("sun:50,30,10,4")->splitSources({}).sources.empty());
  EXPECT_TRUE(loadEnvironment("constant:1")->splitSources({}).sources.empty());
  SourceFinding none;
  none.maxSources = 0;
  EXPECT_TRUE(loadEnvironment("sky")->splitSources(none).sources.empty());
}

TEST(MapSources, ADiscsShCoefficientsAreTheFineLatticesProjection) {
  // projectDisc's closed form against the projection of a 4-degree disc
  // integrated onto a 6x64x64 lattice (texels of 1.4 degrees).
  const CubeLattice lattice(64);
  const auto env = loadEnvironment("sun:60,-40,8,100");
  LatticeLighting l(3 * static_cast<size_t>(lattice.size()), 0.0);
  env->integrate(lattice, Eigen::Matrix3d::Identity(), l);
  const std::array<Rgb, 9> fine = ShProjector(lattice).project(l);
  const std::array<Rgb, 9> closed = projectDisc(env->splitSources({}).sources[0]);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(closed[k][0], fine[k][0], 2e-3 * fine[0][0]) << k;
}

TEST(MapSources, SunFlagValuesAreParsedOrRefusedNamingTheChoices) {
  EXPECT_EQ(parseSourceFinding("auto")->maxSources, SourceFinding{}.maxSources);
  EXPECT_FALSE(parseSourceFinding("off").has_value());
  EXPECT_EQ(parseSourceFinding("2")->maxSources, 2);
  for (const char* bad : {"", "0", "-1", "two", "1.5", "auto,2", "1000"}) {
    try {
      parseSourceFinding(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("auto, off or a count"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace acpca
