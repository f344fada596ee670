// Physical checks of the precompute against closed forms (docs/design.md section 3-4):
// furnace, cosine law, visibility of a sphere, shadows of the step, orientation,
// and determinism across thread counts.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <thread>

#include "core/error.h"
#include "lighting/lighting.h"
#include "precompute/scene.h"
#include "relight/dense_relight.h"
#include "tests/physics/grey_rows.h"
#include "tests/render_support.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

using test::LoadedTransport;
using test::precomputeInMemory;

constexpr double kPi = std::numbers::pi;

/// Grey value (mean over RGB) of every row under one lighting, albedo applied.
std::vector<double> relight(const LoadedTransport& t, const Environment& env,
                            const EnvRotation& rotation = {}) {
  return test::greyRows(t, env, rotation);
}

PrecomputeOptions options(int cubemap, Precision precision = Precision::F32) {
  PrecomputeOptions o;
  o.cubemapResolution = cubemap;
  o.precision = precision;
  return o;
}

Material grey(float a) {
  return {Material::Type::Diffuse, {a, a, a}};
}

/// A diffuse floor seen from straight above, filling the image.
Scene floorScene(int size) {
  return test::floorScene(size, grey(0.8f));
}

TEST(Precompute, FurnaceSphereUnderConstantLightIsHalfEverywhere) {
  for (int cubemap : {16, 32}) {
    Scene scene = makeBuiltinScene("sphere");
    scene.camera.size = {24, 24};
    const LoadedTransport t = precomputeInMemory(scene, options(cubemap, Precision::F16));
    ASSERT_GT(t.header.rows(), 200);
    const auto b = relight(t, *makeConstantEnvironment(Rgb::Constant(1)));
    for (double v : b) ASSERT_NEAR(v, 0.5, 0.5 * 0.005) << "R " << cubemap;
  }
}

TEST(Precompute, CosineLawOnAnUnoccludedFloor) {
  const LoadedTransport t = precomputeInMemory(floorScene(6), options(32));
  ASSERT_EQ(t.header.rows(), 36);
  const double intensity = 500, size = 4;
  const double energy = intensity * 2 * kPi * (1 - std::cos(0.5 * size * kPi / 180));
  for (double theta : {0.0, 30.0, 60.0})
    for (double phi : {0.0, 135.0}) {
      const auto env = makeSunEnvironment(theta, phi, size, Rgb::Constant(intensity));
      const double expected = 0.8 / kPi * energy * std::cos(theta * kPi / 180);
      for (double v : relight(t, *env))
        ASSERT_NEAR(v / expected, 1.0, 0.02) << "theta " << theta << " phi " << phi;
    }
  // A sun wholly below the horizon gives exactly nothing.
  for (double v : relight(t, *makeSunEnvironment(120, 40, size, Rgb::Constant(intensity))))
    EXPECT_EQ(v, 0.0);
}

/// Floor point right below a sphere of radius r at height h, seen from the side.
Scene sphereOverFloor(double r, double h) {
  Scene s{"occluded-floor", {}, {}, {}, {}, {}};
  s.camera.eye = {4, 0.4, 0};
  s.camera.target = {0, 0, 0};
  s.camera.fovDegrees = 20;
  s.camera.size = {9, 9};  // odd: the centre pixel looks exactly at the target
  s.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 200, grey(0.5f), "floor"));
  s.spheres.push_back({{0, h, 0}, r, grey(0.5f)});
  return s;
}

TEST(Precompute, SphereAboveAFloorBlocksItsSolidAngleInClosedForm) {
  const double r = 0.5, h = 1.5;
  const double expected = 0.5 * (1 - (r / h) * (r / h));  // albedo x (1 - (r/h)^2)
  for (auto [texelRays, tolerance] : {std::pair{1, 0.02}, std::pair{16, 0.01}}) {
    PrecomputeOptions o = options(32);
    o.texelRays = texelRays;
    const LoadedTransport t = precomputeInMemory(sphereOverFloor(r, h), o);
    const long long row = test::rowOfPixel(t.header, 4, 4);
    ASSERT_GE(row, 0);
    const double v = relight(t, *makeConstantEnvironment(Rgb::Constant(1)))[row];
    EXPECT_NEAR(v / expected, 1.0, tolerance) << texelRays << " rays per texel";
  }
}

TEST(Precompute, StepCastsItsShadowWhereGeometrySaysUnderALowSun) {
  Scene scene = makeBuiltinScene("step");
  scene.camera.size = {64, 64};
  const LoadedTransport t = precomputeInMemory(scene, options(32, Precision::F16));
  // Sun 20 degrees above the horizon, behind the step (towards -Z): the 0.5 high
  // step at z < 0 shadows the floor for 0 < z < 0.5 / tan(20 deg). The lattice
  // moves the sun by up to half a texel diagonal (2 degrees at R = 32), which
  // moves the shadow's edge: only points clear of that band are checked.
  const double elevation = 20 * kPi / 180;
  const double shadowSure = 0.5 / std::tan(elevation + 2.5 * kPi / 180);
  const double litSure = 0.5 / std::tan(elevation - 2.5 * kPi / 180);
  const auto env = makeSunEnvironment(90 - 20, 0, 2, Rgb::Constant(2000));
  const auto b = relight(t, *env);
  const double lit = 0.6 / kPi * 2000 * 2 * kPi * (1 - std::cos(kPi / 180)) * std::sin(elevation);
  int shadowed = 0, litCount = 0;
  for (long long r = 0; r < t.header.rows(); ++r) {
    const int p = t.header.pixels[r];
    const Vec3 dir = scene.camera.rayDirection(p % 64 + 0.5, p / 64 + 0.5);
    const Vec3 floor = scene.camera.eye - scene.camera.eye.y() / dir.y() * dir;
    if (std::abs(floor.x()) > 4 || t.header.normals[3 * r + 1] < 0.99) continue;  // floor only
    if (floor.z() > 0.1 && floor.z() < shadowSure) {
      EXPECT_LT(b[r], 0.02 * lit) << "z " << floor.z();
      ++shadowed;
    } else if (floor.z() > litSure) {
      EXPECT_NEAR(b[r] / lit, 1.0, 0.05) << "z " << floor.z();
      ++litCount;
    }
  }
  EXPECT_GT(shadowed, 20);
  EXPECT_GT(litCount, 100);
}

/// A sphere seen from above: its visible normals point every way horizontally.
Scene sphereFromAbove() {
  Scene s{"sphere-above", {}, {}, {}, {}, {}};
  s.camera.eye = {0, 6, 0};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 0, -1};
  s.camera.fovDegrees = 25;
  s.camera.size = {24, 24};
  s.spheres.push_back({{0, 0, 0}, 1, grey(0.5f)});
  return s;
}

void expectLitTowards(const LoadedTransport& t, const Environment& env, const Vec3& towards) {
  const auto b = relight(t, env);
  int lit = 0, dark = 0;
  for (long long r = 0; r < t.header.rows(); ++r) {
    const Vec3 n(t.header.normals[3 * r], t.header.normals[3 * r + 1], t.header.normals[3 * r + 2]);
    if (n.dot(towards) > 0.3) {
      EXPECT_GT(b[r], 0) << env.name() << " normal " << n.transpose();
      ++lit;
    } else if (n.dot(towards) < -0.3) {
      EXPECT_EQ(b[r], 0) << env.name() << " normal " << n.transpose();
      ++dark;
    }
  }
  EXPECT_GT(lit, 10);
  EXPECT_GT(dark, 10);
}

TEST(Precompute, LightingConventionsLightTheRightSide) {
  const LoadedTransport t = precomputeInMemory(sphereFromAbove(), options(16));
  expectLitTowards(t, *makeSunEnvironment(90, 90, 4, Rgb::Constant(100)), {1, 0, 0});
  expectLitTowards(t, *makeSunEnvironment(90, 0, 4, Rgb::Constant(100)), {0, 0, -1});
  expectLitTowards(t, *makeSunEnvironment(90, -90, 4, Rgb::Constant(100)), {-1, 0, 0});
  // A lat-long map bright only around u = 0.75 (on the horizon) lights +X.
  const int w = 64, h = 32;
  std::vector<float> rgb(3 * w * h, 0.0f);
  for (int y = 14; y < 18; ++y)
    for (int x = 46; x < 50; ++x)
      for (int c = 0; c < 3; ++c) rgb[3 * (y * w + x) + c] = 50;
  expectLitTowards(t, *makeLatLongEnvironment("bright-u075", w, h, rgb), {1, 0, 0});
  // Yaw +90 turns +X towards -Z (counter-clockwise seen from above).
  const auto env = makeSunEnvironment(90, 90, 4, Rgb::Constant(100));
  const CubeLattice lattice(16);
  const LatticeLighting rotated = computeLighting(*env, lattice, {90, 0, 0});
  Rgb towardsMinusZ = Rgb::Zero(), total = totalEnergy(rotated);
  for (int j = 0; j < lattice.size(); ++j)
    if (lattice.direction(j).z() < -0.9)
      towardsMinusZ += Rgb(rotated[3 * j], rotated[3 * j + 1], rotated[3 * j + 2]);
  EXPECT_NEAR(towardsMinusZ[0] / total[0], 1.0, 1e-9);
}

TEST(Precompute, PhongRowsFollowTheBrdfAndCosine) {
  Scene s = floorScene(3);
  s.meshes[0].material = {Material::Type::Phong, {0.5f, 0.5f, 0.5f}, 0.6, 80};
  const LoadedTransport t = precomputeInMemory(s, options(16));
  const CubeLattice lattice(16);
  const long long row = test::rowOfPixel(t.header, 1, 1);  // looks straight down
  const Vec3 n(0, 1, 0), toViewer(0, 1, 0), tangent(1, 0, 0);
  for (int j = 0; j < lattice.size(); ++j) {
    const Vec3& d = lattice.direction(j);
    const double expected =
        d.y() > 0 ? d.y() * brdfShape(s.meshes[0].material, n, tangent, toViewer, d) : 0;
    ASSERT_NEAR(t.row(row)[j], expected, 1e-4 * (1 + expected)) << j;
  }
}

TEST(Precompute, SameTransportWithOneAndTwoThreads) {
  Scene scene = makePlantScene();
  scene.camera.size = {48, 48};
  PrecomputeOptions one = options(8, Precision::F16), two = one;
  one.threads = 1;
  two.threads = 2;
  const LoadedTransport a = precomputeInMemory(scene, one), b = precomputeInMemory(scene, two);
  EXPECT_EQ(a.stats.threadsUsed, 1);
  EXPECT_EQ(b.stats.threadsUsed, 2) << "the two-thread run did not use two threads";
  EXPECT_EQ(a.header.pixels, b.header.pixels);
  EXPECT_EQ(a.header.albedo, b.header.albedo);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  EXPECT_TRUE(std::equal(a.rows.begin(), a.rows.end(), b.rows.begin()));
  EXPECT_GT(a.stats.occlusionRays, 0);
  EXPECT_EQ(a.stats.occlusionRays, b.stats.occlusionRays);
}

TEST(Precompute, EqualRunsWriteEqualBytesWhenever) {
  // HDF5 stamps objects with their creation time unless told not to.
  Scene scene = makeBuiltinScene("sphere");
  scene.camera.size = {12, 12};
  test::TempDir dir;
  const auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  precomputeTransport(scene, dir.file("a.h5"), options(4));
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  precomputeTransport(scene, dir.file("b.h5"), options(4));
  const std::string a = bytes(dir.file("a.h5"));
  EXPECT_GT(a.size(), 1000u);
  EXPECT_TRUE(a == bytes(dir.file("b.h5")));
}

TEST(Precompute, SupersampledSilhouettesHaveFractionalCoverage) {
  Scene scene = makeBuiltinScene("sphere");
  scene.camera.size = {16, 16};
  PrecomputeOptions o = options(8);
  o.samplesPerPixel = 8;
  const LoadedTransport t = precomputeInMemory(scene, o);
  int partial = 0;
  for (float c : t.header.coverage) {
    EXPECT_GT(c, 0);
    EXPECT_LE(c, 1);
    partial += c < 1;
  }
  EXPECT_GT(partial, 8);
  // The furnace still holds for the covered part of every pixel.
  for (double v : relight(t, *makeConstantEnvironment(Rgb::Constant(1)))) EXPECT_NEAR(v, 0.5, 0.01);
}

TEST(Precompute, RefusesBadOptionsBeforeAnyWork) {
  test::TempDir dir;
  const Scene scene = makeBuiltinScene("sphere");
  PrecomputeOptions o;
  o.cubemapResolution = 0;
  EXPECT_THROW(precomputeTransport(scene, dir.file("t.h5"), o), UserError);
  o = {};
  o.samplesPerPixel = 0;
  EXPECT_THROW(precomputeTransport(scene, dir.file("t.h5"), o), UserError);
  o = {};
  EXPECT_THROW(precomputeTransport(scene, dir.file("missing/t.h5"), o), UserError);
  EXPECT_TRUE(test::fs::is_empty(dir.path()));
}

}  // namespace
}  // namespace acpca
