// Local lights relit from a rendered transport against closed forms: a sphere
// light and a point light over an unoccluded diffuse floor, and the
// linearity of light (doubling, sums of lights).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "precompute/scene.h"
#include "precompute/sphere_light_reference.h"
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
      const double expected = kAlbedo * light.emission.x() *
                              std::pow(light.as<SphereLight>()->radius / d, 2) * cosTheta;
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

/// Relative L2 of a against b, RGB rows.
double relativeL2(const std::vector<float>& a, const std::vector<float>& b) {
  double err = 0, norm = 0;
  for (size_t i = 0; i < a.size(); ++i) err += std::pow(a[i] - b[i], 2), norm += std::pow(b[i], 2);
  return std::sqrt(err / norm);
}

TEST(LocalLights, TheDenseRelightMatchesShadowRaysToTheSphereFromTwoToFiftyRadii) {
  // An outside reference: Embree's shadow rays from each camera sample to
  // 400 points of the sphere's cone, times the BRDF and cosine. The lattice
  // knows the transport per texel only, so a disc inside one texel is seen
  // along the texel's centre, up to half a texel diagonal (0.035 rad at
  // R = 32) from the light: a relative error up to tan(theta) x 0.035 for a
  // diffuse floor lit from theta off its normal. Larger discs average over
  // their texels, an error of second order.
  const Floor floor;
  const TransportReader t(floor.path);
  const Scene scene = test::floorScene(24, {Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}});
  const double radius = 0.05, halfDiagonal = 0.5 * std::sqrt(2.0) * (0.5 * kPi / 32);
  for (double radii : {2.0, 5.0, 20.0, 50.0}) {
    const Vec3 centre(0.1, radius * radii, -0.05);
    const LocalLight light = parseLocalLight(
        concat("sphere:", centre.x(), ",", centre.y(), ",", centre.z(), ",", radius, ",10"));
    const auto dense = denseLocalRelight(t, {light});
    const auto reference =
        renderSphereLightReference(scene, {centre, radius, Eigen::Vector3d::Constant(10)}, 1, 400);
    ASSERT_EQ(dense.size(), reference.size());
    double worstExcess = 0;
    for (long long r = 0; r < t.rows(); ++r) {
      const Vec3 toLight = centre - positionOf(t.header(), r);
      const double tanTheta = std::hypot(toLight.x(), toLight.z()) / toLight.y();
      const double bound = tanTheta * halfDiagonal + 0.005;  // + the reference's noise
      const double error = std::abs(dense[3 * r] / reference[3 * r] - 1);
      worstExcess = std::max(worstExcess, error - bound);
    }
    EXPECT_LE(worstExcess, 0) << radii << " radii";
    RecordProperty(concat("relative_l2 at ", radii, " radii"),
                   std::to_string(relativeL2(dense, reference)));
  }
}

/// A floor with a box on it, a sphere light at `lightHeight` above it, and
/// the dense relight from its transport beside the shadow-ray reference.
struct BoxUnderALamp {
  test::TempDir dir;
  std::vector<float> dense, reference;
  BoxUnderALamp(const Vec3& boxLo, const Vec3& boxHi, const Vec3& centre, double radius,
                const Vec3& eye = {0, 5, 0}) {
    Scene s = test::floorScene(32, {Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}});
    s.camera.eye = eye;
    if (eye.x() != 0) s.camera.up = {0, 1, 0}, s.camera.fovDegrees = 50;
    s.meshes.push_back(makeBox(boxLo, boxHi, {Material::Type::Diffuse, {0.5f, 0.5f, 0.5f}}, "box"));
    PrecomputeOptions o;
    o.cubemapResolution = 32;
    o.precision = Precision::F32;
    o.samplesPerPixel = 1;
    const std::string path = dir.file("t.h5");
    precomputeTransport(s, path, o);
    const TransportReader t(path);
    dense = denseLocalRelight(t, {parseLocalLight(concat("sphere:", centre.x(), ",", centre.y(),
                                                         ",", centre.z(), ",", radius, ",10"))});
    reference =
        renderSphereLightReference(s, {centre, radius, Eigen::Vector3d::Constant(10)}, 1, 400);
  }
};

TEST(LocalLights, AShadowBetweenLampAndFloorAgreesUpToItsPenumbraOnTheLattice) {
  // The box's shadow edge falls where the lattice's texel centres say:
  // pixels within the penumbra's width of a texel may be lit or not. The
  // image agrees to a few percent.
  const BoxUnderALamp scene({-0.15, 0, -0.15}, {0.15, 0.3, 0.15}, {0.2, 1.2, 0.1}, 0.08);
  const double err = relativeL2(scene.dense, scene.reference);
  EXPECT_LT(err, 0.05);
  RecordProperty("relative_l2", std::to_string(err));
}

TEST(LocalLights, AnOccluderBehindTheLampShadowsItInTheTransportButNotInTruth) {
  // docs/lighting.md, "Local lights": visibility was traced to infinity. A
  // slab above a low lamp, seen from the side, blocks every floor pixel's
  // ray to the lamp beyond it: the reference sees the lamp, the transport
  // does not.
  const BoxUnderALamp scene({-4, 0.6, -4}, {4, 0.7, 4}, {0, 0.3, 0}, 0.05, {2.5, 0.35, 0});
  double dense = 0, reference = 0;
  for (size_t i = 0; i < scene.dense.size(); ++i)
    dense += scene.dense[i], reference += scene.reference[i];
  EXPECT_GT(reference, 0);
  EXPECT_LT(dense, 0.01 * reference);
}

TEST(LocalLights, ALightOnTheFloorIsRefusedNamingItAndThePixel) {
  const Floor floor;
  const TransportReader t(floor.path);
  try {
    requireLocalLightsApply(t.header(), t.path(), false, {parseLocalLight("sphere:0,0,0,0.3,1")});
    FAIL() << "a sphere through the floor was accepted";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.value(), "sphere:0,0,0,0.3,1");
    EXPECT_NE(e.problem().find("pixel position(s) of " + floor.path), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace acpca
