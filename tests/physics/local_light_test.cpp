// Local lights relit from a rendered transport against closed forms: a sphere
// light and a point light over an unoccluded diffuse floor, and the
// linearity of light (doubling, sums of lights).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "relight/local_relight.h"
#include "tests/render_support.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kAlbedo = 0.8f;

/// A diffuse floor seen from straight above, and its transport at R = 32.
struct Floor {
  test::TempDir dir;
  std::string path = dir.file("floor.h5");
  Floor() {
    const Scene s = test::floorScene(24, {Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}});
    PrecomputeOptions o;
    o.cubemapResolution = 32;
    o.precision = Precision::F32;
    precomputeTransport(s, path, o);
  }
};

Vec3 positionOf(const TransportHeader& h, long long r) {
  return {h.positions[3 * r], h.positions[3 * r + 1], h.positions[3 * r + 2]};
}

TEST(LocalLights, ASphereOverAFloorGivesTheClosedFormOfASphericalSource) {
  // Irradiance from a uniform sphere wholly above a surface's horizon:
  // pi L (r/d)^2 cos(theta), so a diffuse floor shows a L (r/d)^2 cos(theta).
  const Floor floor;
  const TransportReader t(floor.path);
  ASSERT_TRUE(t.header().hasPositions());
  for (const char* spec : {"sphere:0.3,1.5,-0.2,0.4,10", "sphere:-0.2,0.9,0.1,0.15,40"}) {
    const LocalLight light = parseLocalLight(spec);
    const std::vector<float> rgb = denseLocalRelight(t, {light});
    double worst = 0;
    for (long long r = 0; r < t.rows(); ++r) {
      const Vec3 toLight = light.position - positionOf(t.header(), r);
      const double d = toLight.norm(), cosTheta = toLight.y() / d;
      const double expected =
          kAlbedo * light.emission.x() * std::pow(light.radius / d, 2) * cosTheta;
      worst = std::max(worst, std::abs(rgb[3 * r] / expected - 1));
    }
    EXPECT_LT(worst, 0.01) << spec;
    RecordProperty(std::string("worst_relative_error ") + spec, std::to_string(worst));
  }
}

TEST(LocalLights, APointLightOverAFloorFollowsTheInverseSquareAndCosineLaws) {
  const Floor floor;
  const TransportReader t(floor.path);
  const LocalLight light = parseLocalLight("point:0.2,1,0.1,3");
  const std::vector<float> rgb = denseLocalRelight(t, {light});
  for (long long r = 0; r < t.rows(); ++r) {
    const Vec3 toLight = light.position - positionOf(t.header(), r);
    const double d = toLight.norm();
    const double expected = kAlbedo * 3 * (toLight.y() / d) / (kPi * d * d);
    ASSERT_NEAR(rgb[3 * r] / expected, 1, 0.005) << "row " << r;
  }
}

TEST(LocalLights, LightAddsUpDoublingDoublesAndTwoLightsAreTheSumOfEach) {
  const Floor floor;
  const TransportReader t(floor.path);
  const LocalLight a = parseLocalLight("point:0.2,1,0.1,3,2,1"),
                   b = parseLocalLight("sphere:-0.5,1.2,0.4,0.2,7"),
                   a2 = parseLocalLight("point:0.2,1,0.1,6,4,2");
  const auto alone = denseLocalRelight(t, {a}), other = denseLocalRelight(t, {b});
  const auto doubled = denseLocalRelight(t, {a2}), both = denseLocalRelight(t, {a, b});
  for (size_t i = 0; i < alone.size(); ++i) {
    EXPECT_EQ(doubled[i], 2 * alone[i]) << "doubling is exact in binary floating point";
    EXPECT_NEAR(both[i], alone[i] + other[i], 1e-6 * (alone[i] + other[i]));
  }
}

TEST(LocalLights, ALightOnTheFloorIsRefusedNamingItAndThePixel) {
  const Floor floor;
  const TransportReader t(floor.path);
  try {
    denseLocalRelight(t, {parseLocalLight("sphere:0,0,0,0.3,1")});
    FAIL() << "a sphere through the floor was accepted";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.value(), "sphere:0,0,0,0.3,1");
    EXPECT_NE(e.problem().find("pixel position(s) of " + floor.path), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace acpca
