// Sphere lamps lit exactly (relight/sphere_lamp.h): the closed form over an
// open floor with no ray past the probes, the energy of the lattice path,
// a penumbra as wide as its closed form, shadow rays rendered apart, the
// same bytes for any thread count, and a spot of half angle 90 degrees.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "cluster/compress.h"
#include "core/error.h"
#include "model/model_file.h"
#include "precompute/scene.h"
#include "precompute/sphere_light_reference.h"
#include "precompute/transport_renderer.h"
#include "relight/lamp_light.h"
#include "relight/local_relight.h"
#include "relight/relight_source.h"
#include "relight/sphere_lamp.h"
#include "tests/physics/penumbra_profile.h"
#include "tests/render_support.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kAlbedo = 0.8f;
const Material kGrey{Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}};

std::vector<float> lampRows(const std::string& path, const std::string& spec,
                            const LampSettings& settings = {}) {
  const RelightSource source = openRelightSource(path);
  return source.relightLocal({parseLocalLight(spec)}, kAnchorSpreadTexels, settings);
}

Vec3 positionOf(const TransportHeader& h, long long r) {
  return {h.positions[3 * r], h.positions[3 * r + 1], h.positions[3 * r + 2]};
}

std::string precomputed(const test::TempDir& dir, const Scene& s, int resolution) {
  const std::string path = dir.file("t.h5");
  PrecomputeOptions o;
  o.cubemapResolution = resolution;
  o.samplesPerPixel = 1;
  o.precision = Precision::F32;
  precomputeTransport(s, path, o);
  return path;
}

TEST(SphereLamps, AnOpenFloorIsTheClosedFormWithNoRayPastTheProbes) {
  // A diffuse floor sees a whole sphere above its horizon: a L (r/d)^2
  // cos(theta) at every pixel; every probe reaches the lamp, so no row
  // traces strata; and the energy is the lattice path's.
  const test::TempDir dir;
  const std::string path = precomputed(dir, test::floorScene(48, kGrey), 32);
  const TransportReader t(path);
  for (const char* spec : {"sphere:0.3,1.5,-0.2,0.4,10", "sphere:-0.2,0.6,0.1,0.15,40"}) {
    const LocalLight light = parseLocalLight(spec);
    const std::vector<float> exact = lampRows(path, spec);
    const std::vector<float> lattice = lampRows(path, spec, LampMode::Lattice);
    double exactSum = 0, latticeSum = 0;
    for (long long r = 0; r < t.rows(); ++r) {
      const Vec3 toLight = light.position - positionOf(t.header(), r);
      const double d = toLight.norm();
      const double expected = kAlbedo * light.emission.x() *
                              std::pow(light.as<SphereLight>()->radius / d, 2) * toLight.y() / d;
      ASSERT_NEAR(exact[3 * r] / expected, 1, 1e-5) << spec << " row " << r;
      exactSum += exact[3 * r], latticeSum += lattice[3 * r];
    }
    EXPECT_NEAR(exactSum / latticeSum, 1, 0.005) << spec;
    RecordProperty(concat("energy exact / lattice ", spec), std::to_string(exactSum / latticeSum));
    const SceneOccluder occluder(t.header().lamps);
    std::atomic<long long> probes{0};
    const auto sight = sphereLampSight(t.header(), occluder,
                                       CapLamp::sphere(light, *light.as<SphereLight>()), probes);
    EXPECT_EQ(std::count(sight.begin(), sight.end(), LampSight::Whole), t.rows()) << spec;
    // One ray a sample, the probe, and no more.
    const ExactLamps lamps(t.header());
    lamps.relight({light});
    EXPECT_EQ(lamps.shadowRays(), t.header().lamps.samples()) << spec;
    EXPECT_EQ(probes, t.header().lamps.samples()) << spec;
  }
}

TEST(SphereLamps, APenumbraOnAFloorIsAsWideAsItsClosedForm) {
  // A thin slab whose edge runs along z at (-0.5, kEdgeY) shades the floor
  // from a sphere up to the left. A floor point sees the part of the lamp
  // beyond the plane through it and the edge; that plane's distance from
  // the centre, over the radius, is t (in the xy plane: nothing depends on
  // z but the lamp's distance). The light falls from the whole lamp's to
  // none where t goes from 1 to -1: the penumbra. Its width between 10% and
  // 90% of the unshadowed light, measured across the image's middle rows,
  // against the same from the disc's segments.
  constexpr double kEdgeX = -0.5, kEdgeY = 1.001, kRadius = 0.3;
  const Vec3 centre(-2.5, 3, 0);
  Scene s = test::floorScene(128, kGrey);
  s.meshes.push_back(makeBox({-6, 1, -6}, {kEdgeX, kEdgeY, 6}, kGrey, "slab"));
  const test::TempDir dir;
  const std::string path = precomputed(dir, s, 8);
  const TransportReader t(path);
  const std::string spec = concat("sphere:", centre.x(), ",", centre.y(), ",0,", kRadius, ",50");
  for (const int rays : {16, kDefaultSphereLampRays}) {
    const std::vector<float> rows = lampRows(path, spec, {LampMode::Exact, rays});
    const auto signedT = [&](double x) {  // the line from (x, 0) through the edge
      const Eigen::Vector2d from(x, 0), along = Eigen::Vector2d(kEdgeX, kEdgeY) - from;
      const Eigen::Vector2d toCentre = Eigen::Vector2d(centre.x(), centre.y()) - from;
      return (along.y() * toCentre.x() - along.x() * toCentre.y()) / along.norm() / kRadius;
    };
    // The lit share per image column over the middle rows (|z| < 0.06).
    const test::ShareProfile profile =
        test::floorColumnProfile(t.header(), rows, 0.06, [&](const Vec3& p) {
          const Vec3 toLight = centre - p;
          const double d = toLight.norm();
          return kAlbedo * 50 * std::pow(kRadius / d, 2) * toLight.y() / d;
        });
    ASSERT_GT(profile.size(), 100u);
    EXPECT_LT(profile.front().second, 1e-6);         // the umbra, every ray blocked
    EXPECT_NEAR(profile.back().second, 1, 1e-5);     // the whole lamp, in closed form
    const auto closedCrossing = [&](double share) {  // the share grows with x
      return test::risingCrossing([&](double x) { return test::visibleShare(signedT(x)); }, share,
                                  -0.5, 1.5);
    };
    const double measured =
        test::profileCrossing(profile, 0.9) - test::profileCrossing(profile, 0.1);
    const double expected = closedCrossing(0.9) - closedCrossing(0.1);
    EXPECT_NEAR(measured / expected, 1, 0.05)
        << measured << " against " << expected << ", " << rays << " rays";
    RecordProperty(concat("penumbra_width_10_90 rays ", rays), std::to_string(measured));
    RecordProperty("closed_form_width_10_90", std::to_string(expected));
  }
}

TEST(SphereLamps, ABoxShadowMatchesShadowRaysRenderedApartFromTransportAndModel) {
  // A box on the floor under a sphere lamp: the exact rows against Embree's
  // shadow rays to 400 strata of the lamp's cone (precompute/
  // sphere_light_reference.h), rendered apart; the model lights the lamp as
  // its transport does, and one thread as two.
  Scene s = test::floorScene(64, kGrey);
  s.meshes.push_back(makeBox({-0.2, 0, -0.2}, {0.2, 0.3, 0.2}, kGrey, "box"));
  const test::TempDir dir;
  const std::string path = precomputed(dir, s, 8), model = dir.file("m.h5");
  writeModel(compressTransport(TransportReader(path), CompressOptions{}), model);
  const Vec3 centre(0.9, 1.1, 0.3);
  const double radius = 0.25;
  const std::string spec =
      concat("sphere:", centre.x(), ",", centre.y(), ",", centre.z(), ",", radius, ",10");
  const auto reference =
      renderSphereLightReference(s, {centre, radius, Eigen::Vector3d::Constant(10)}, 1, 400);
  // Fewer rays add noise in the penumbra, nothing else.
  for (const auto& [rays, bound] : {std::pair{16, 0.02}, std::pair{kDefaultSphereLampRays, 0.01}}) {
    const std::vector<float> rows = lampRows(path, spec, {LampMode::Exact, rays});
    ASSERT_EQ(rows.size(), reference.size());
    double err = 0, norm = 0;
    for (size_t i = 0; i < rows.size(); ++i)
      err += std::pow(double(rows[i]) - reference[i], 2), norm += std::pow(double(reference[i]), 2);
    EXPECT_LT(std::sqrt(err / norm), bound) << rays << " rays";
    RecordProperty(concat("relative_l2_against_shadow_rays rays ", rays),
                   std::to_string(std::sqrt(err / norm)));
  }
  const std::vector<float> exact = lampRows(path, spec);
  EXPECT_EQ(lampRows(model, spec), exact);
  tbb::task_arena one(1);
  EXPECT_EQ(one.execute([&] { return lampRows(path, spec); }), exact);
}

TEST(SphereLamps, ASpotOfHalfAngleNinetyDegreesLightsItsHalfSpace) {
  // Pointing along +x from above the floor's middle: as the point lamp
  // inside 0.9 x 90 degrees of its axis, dark behind it.
  const test::TempDir dir;
  const std::string path = precomputed(dir, test::floorScene(32, kGrey), 8);
  const TransportReader t(path);
  const std::vector<float> spot = lampRows(path, "spot:0,1,0,1,0,0,90,3");
  const std::vector<float> point = lampRows(path, "point:0,1,0,3");
  int lit = 0, dark = 0;
  for (long long r = 0; r < t.rows(); ++r) {
    const Vec3 toPixel = (positionOf(t.header(), r) - Vec3(0, 1, 0)).normalized();
    const double degrees = std::acos(toPixel.x()) * 180 / kPi;
    if (degrees < 80.9) {
      EXPECT_FLOAT_EQ(spot[3 * r], point[3 * r]);
      ++lit;
    }
    if (degrees > 90.1) {
      EXPECT_EQ(spot[3 * r], 0.0f);
      ++dark;
    }
  }
  EXPECT_GT(lit, 100);
  EXPECT_GT(dark, 100);
}

TEST(SphereLamps, LampRaysAreASquareFromFourTo256) {
  EXPECT_EQ(parseSphereLampRays("4"), 4);
  EXPECT_EQ(parseSphereLampRays("64"), 64);
  EXPECT_EQ(parseSphereLampRays("256"), 256);
  for (const char* bad : {"1", "50", "289", "0", "-16", "16x", "", "abc", "1e9"}) {
    try {
      parseSphereLampRays(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const ParameterError& e) {
      EXPECT_EQ(e.value(), bad);
      EXPECT_NE(std::string(e.what()).find("square from 4 to 256"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace acpca
