// Anisotropic materials through the whole precompute and the exact lamps
// (transport/material.h, docs/scenes.md "Materials" and "Tangents"):
// reciprocity and energy of the materials as the renderer evaluates them,
// the highlight of a point lamp on a plane elongated as each axis' exponent
// says, a quarter turn swapping the axes bit for bit, equal axes giving the
// isotropic lobe, the tangent label, and files from before tangents.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <numbers>
#include <random>

#include "dataset/file_info.h"
#include "dataset/pixel_labels.h"
#include "precompute/embree_scene.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "relight/local_relight.h"
#include "relight/relight_source.h"
#include "tests/render_support.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;

Material ashikhminShirley(double nu, double nv, double rs, double rotation = 0) {
  Material m;
  m.type = Material::Type::AshikhminShirley;
  m.albedo.setConstant(0.8f);
  m.specular = rs, m.nu = nu, m.nv = nv, m.rotationDegrees = rotation;
  return m;
}

Material anisotropicGgx(double au, double av, double ks, double rotation = 0) {
  Material m;
  m.type = Material::Type::Ggx;
  m.albedo.setConstant(0.8f);
  m.specular = ks, m.roughness = au, m.roughnessV = av, m.rotationDegrees = rotation;
  return m;
}

Vec3 randomUpper(std::mt19937& rng, const Vec3& n) {
  std::normal_distribution<double> g;
  Vec3 d(g(rng), g(rng), g(rng));
  if (d.dot(n) < 0) d = -d;
  return d.normalized();
}

TEST(AnisotropicMaterials, AreReciprocalAndTheFloatLobeIsTheDoubleOne) {
  std::mt19937 rng(5);
  const Vec3 n = Vec3(0.3, 0.9, -0.2).normalized();
  const Vec3 t = tangentAcross(n, Vec3(1, 0, 0));
  for (const Material& m : {ashikhminShirley(40, 10, 0.3), anisotropicGgx(0.4, 0.08, 0.7)}) {
    for (int k = 0; k < 2000; ++k) {
      const Vec3 i = randomUpper(rng, n), o = randomUpper(rng, n);
      const double forward = brdfShape(m, n, t, o, i), backward = brdfShape(m, n, t, i, o);
      ASSERT_NEAR(forward, backward, 1e-12 * std::max(1.0, forward));
      const LobeShape shape(m, n.cast<float>(), t.cast<float>(), o.cast<float>());
      const float single = shape(float(i.x()), float(i.y()), float(i.z()), float(n.dot(i)));
      ASSERT_NEAR(single, forward, 2e-4 * std::max(1.0, forward));
    }
  }
}

TEST(AnisotropicMaterials, ReflectAtMostWhatArrivesAtFullSpecular) {
  // The directional albedo, the integral of f cos over incoming directions,
  // at ks = 1 over a grid of view directions (midpoint rule in theta, phi).
  const Vec3 n(0, 0, 1), t(1, 0, 0);
  const int steps = 200;
  for (const Material& m : {ashikhminShirley(40, 10, 1), anisotropicGgx(0.3, 0.05, 1)}) {
    for (double thetaO : {0.0, 0.4, 0.8, 1.2, 1.45})
      for (double phiO : {0.0, 0.7, 1.57}) {
        const Vec3 o(std::sin(thetaO) * std::cos(phiO), std::sin(thetaO) * std::sin(phiO),
                     std::cos(thetaO));
        const double dTheta = 0.5 * kPi / steps, dPhi = 2 * kPi / (4 * steps);
        double albedo = 0;
        for (int a = 0; a < steps; ++a)
          for (int b = 0; b < 4 * steps; ++b) {
            const double theta = (a + 0.5) * dTheta, phi = (b + 0.5) * dPhi;
            const Vec3 i(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta));
            albedo += brdfShape(m, n, t, o, i) * i.z() * std::sin(theta) * dTheta * dPhi;
          }
        EXPECT_LE(albedo, 1.0 + 1e-3) << kMaterialTypeNames.name(m.type) << " at " << thetaO;
        EXPECT_GT(albedo, 0.3);
      }
  }
}

TEST(AnisotropicMaterials, EqualAxesGiveTheIsotropicLobeWhateverTheTangent) {
  std::mt19937 rng(9);
  const Vec3 n(0, 0, 1), t(1, 0, 0), turned = Vec3(1, 2, 0).normalized();
  Material iso;
  iso.type = Material::Type::Ggx, iso.specular = 0.6, iso.roughness = 0.2;
  const Material equalGgx = anisotropicGgx(0.2, 0.2, 0.6), equalAs = ashikhminShirley(25, 25, 0.4);
  for (int k = 0; k < 500; ++k) {
    const Vec3 i = randomUpper(rng, n), o = randomUpper(rng, n);
    const double isotropic = brdfShape(iso, n, t, o, i);
    EXPECT_NEAR(brdfShape(equalGgx, n, turned, o, i), isotropic, 1e-9 * std::max(1.0, isotropic));
    // The anisotropic form's formula with the two alphas equal.
    const Vec3 h = (i + o).normalized();
    const auto in = [&](const Vec3& d) { return FrameComponents<double>{d.x(), d.y(), d.z()}; };
    const double general =
        (1 - 0.6) / kPi + 0.6 * anisotropicGgxSpecular(in(i), in(o), in(h), 0.2, 0.2);
    EXPECT_NEAR(general, isotropic, 1e-9 * std::max(1.0, isotropic));
    EXPECT_NEAR(brdfShape(equalAs, n, t, o, i), brdfShape(equalAs, n, turned, o, i),
                1e-9 * std::max(1.0, brdfShape(equalAs, n, t, o, i)));
  }
}

/// A floor through the origin under a wide camera straight above it.
Scene wideFloor(const Material& m, int size) {
  Scene s = test::floorScene(size, m);
  s.camera.fovDegrees = 80;
  return s;
}

TEST(AnisotropicMaterials, AQuarterTurnSwapsTheAxesBitForBit) {
  PrecomputeOptions o;
  o.cubemapResolution = 8;
  o.precision = Precision::F32;
  const auto rows = [&](const Material& m) {
    return test::precomputeInMemory(wideFloor(m, 24), o).rows;
  };
  EXPECT_EQ(rows(ashikhminShirley(40, 10, 0.5, 90)), rows(ashikhminShirley(10, 40, 0.5)));
  EXPECT_EQ(rows(anisotropicGgx(0.3, 0.05, 0.5, -90)), rows(anisotropicGgx(0.05, 0.3, 0.5)));
  EXPECT_NE(rows(ashikhminShirley(40, 10, 0.5)), rows(ashikhminShirley(10, 40, 0.5)));
}

/// Where along one axis of the floor (x or z through the origin) a point
/// lamp at the camera's eye is lit to half its peak, in half-vector angle:
/// with the lamp at the eye the half vector is the view direction.
double halfMaximumAngle(const TransportHeader& h, const std::vector<float>& rgb, int axis) {
  std::vector<std::pair<double, double>> profile;  // (angle, value / irradiance)
  const Vec3 eye = h.camera.eye;
  for (long long r = 0; r < h.rows(); ++r) {
    const Vec3 p(h.positions[3 * r], h.positions[3 * r + 1], h.positions[3 * r + 2]);
    if (std::abs(p[2 - axis]) > 0.05 || p[axis] < 0) continue;  // one half-line of the axis
    const Vec3 toEye = eye - p;
    const double angle = std::acos(toEye.normalized().y());
    profile.emplace_back(angle, rgb[3 * r] * toEye.squaredNorm());
  }
  std::sort(profile.begin(), profile.end());
  const double half = 0.5 * profile.front().second;
  for (size_t k = 1; k < profile.size(); ++k)
    if (profile[k].second < half) {
      const auto [a0, v0] = profile[k - 1];
      const auto [a1, v1] = profile[k];
      return a0 + (a1 - a0) * (v0 - half) / (v0 - v1);
    }
  return -1;
}

TEST(AnisotropicMaterials, APointLampsHighlightIsElongatedAsEachExponentSays) {
  // Rs = 1: no diffuse term and a Fresnel factor of 1, so with the lamp at the
  // eye a pixel's light over the lamp's irradiance is the lobe times cos:
  // a constant times (n.h)^(nu cos^2 phi + nv sin^2 phi). Along the tangent
  // (world +X) it falls to half at acos(2^(-1/nu)), across it at acos(2^(-1/nv)).
  const test::TempDir dir;
  const std::string path = dir.file("floor.h5");
  PrecomputeOptions o;
  o.cubemapResolution = 4;
  o.samplesPerPixel = 1;
  precomputeTransport(wideFloor(ashikhminShirley(40, 10, 1), 241), path, o);
  const RelightSource source = openRelightSource(path);
  const std::vector<float> rgb = source.relightLocal({parseLocalLight("point:0,5,0,100")},
                                                     kAnchorSpreadTexels, LampMode::Exact);
  const TransportReader t(path);
  const double alongT = halfMaximumAngle(t.header(), rgb, 0);
  const double alongB = halfMaximumAngle(t.header(), rgb, 2);
  const double expectedT = std::acos(std::pow(2.0, -1.0 / 40)),
               expectedB = std::acos(std::pow(2.0, -1.0 / 10));
  ASSERT_GT(alongT, 0);
  ASSERT_GT(alongB, 0);
  EXPECT_NEAR(alongT / expectedT, 1, 0.05) << alongT * 180 / kPi << " degrees";
  EXPECT_NEAR(alongB / expectedB, 1, 0.05) << alongB * 180 / kPi << " degrees";
  EXPECT_NEAR((alongB / alongT) / (expectedB / expectedT), 1, 0.05);
  // The file records the material, and `info` prints it.
  const TransportSummary summary = readTransportSummary(path);
  ASSERT_EQ(summary.pixels.materials.size(), 1u);
  EXPECT_EQ(summary.pixels.materials[0].nu, 40);
  EXPECT_NE(describeInWords(summary, path).find("materials    ashikhmin-shirley rs 1 nu 40 nv 10"),
            std::string::npos)
      << describeInWords(summary, path);
}

TEST(AnisotropicMaterials, TheTangentLabelIsWorldXAcrossTheNormalTurnedByTheRotation) {
  PrecomputeOptions o;
  o.cubemapResolution = 4;
  for (double rotation : {0.0, 30.0}) {
    const test::LoadedTransport t =
        test::precomputeInMemory(wideFloor(ashikhminShirley(40, 10, 0.5, rotation), 16), o);
    const std::vector<LabelLayer> layers = viewLabels(t.header, {Aov::Tangent});
    ASSERT_EQ(layers.size(), 1u);
    EXPECT_EQ(layers[0].channels, (std::vector<std::string>{"T.X", "T.Y", "T.Z"}));
    // About +Y, counter-clockwise: +X turns towards +Y x +X = -Z.
    const double a = rotation * kPi / 180;
    for (long long r = 0; r < t.header.rows(); ++r) {
      const float* v = &layers[0].values[3 * size_t(t.header.pixels[r])];
      EXPECT_NEAR(v[0], std::cos(a), 1e-6);
      EXPECT_NEAR(v[1], 0, 1e-6);
      EXPECT_NEAR(v[2], -std::sin(a), 1e-6);
    }
  }
}

TEST(AnisotropicMaterials, SphereTangentsRunAlongTheParallelsAboutY) {
  Scene s = test::floorScene(8, Material{});
  s.meshes.clear();
  s.spheres.push_back({{0, 0, 0}, 1, ashikhminShirley(40, 10, 0.5)});
  const EmbreeScene embree(s);
  std::mt19937 rng(3);
  for (int k = 0; k < 200; ++k) {
    const Vec3 target = randomUpper(rng, Vec3(0, 1, 0)) * 0.9;
    const Vec3 eye(0.3, 5, 0.2);
    const EmbreeScene::Hit hit = embree.intersect(eye, (target - eye).normalized());
    ASSERT_GE(hit.material, 0);
    EXPECT_NEAR(hit.tangent.norm(), 1, 1e-12);
    EXPECT_NEAR(hit.tangent.dot(hit.shadingNormal), 0, 1e-12);
    EXPECT_NEAR(hit.tangent.y(), 0, 1e-12);  // horizontal: along a parallel
  }
  // A plane whose normal is along X takes +Z.
  Scene wall = test::floorScene(8, ashikhminShirley(40, 10, 0.5));
  wall.meshes = {makeQuad({0, 0, 0}, {1, 0, 0}, 4, ashikhminShirley(40, 10, 0.5), "wall")};
  const EmbreeScene walls(wall);
  const EmbreeScene::Hit hit = walls.intersect({3, 0.1, 0.2}, {-1, 0, 0});
  ASSERT_GE(hit.material, 0);
  EXPECT_NEAR(std::abs(hit.tangent.z()), 1, 1e-12);
}

TEST(AnisotropicMaterials, FilesFromBeforeTangentsAreReadAsIsotropic) {
  // A transport of an isotropic scene, made to look like version 5 (no
  // tangents, four material columns): it lights a lamp exactly as before,
  // and refuses the tangent label naming what to run again.
  const test::TempDir dir;
  const std::string path = dir.file("floor.h5");
  Material ggx;
  ggx.type = Material::Type::Ggx, ggx.specular = 0.5, ggx.roughness = 0.3;
  PrecomputeOptions o;
  o.cubemapResolution = 4;
  precomputeTransport(test::floorScene(16, ggx), path, o);
  const std::vector<float> before = openRelightSource(path).relightLocal(
      {parseLocalLight("point:0.3,1,0.2,3")}, kAnchorSpreadTexels, LampMode::Exact);
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Ldelete(f, "lamp_sample_tangent", H5P_DEFAULT);
    H5Ldelete(f, "lamp_materials", H5P_DEFAULT);
    const double table[4] = {2, 0.5, 1, 0.3};
    const hsize_t shape[2] = {1, 4};
    const hid_t space = H5Screate_simple(2, shape, nullptr);
    const hid_t set = H5Dcreate2(f, "lamp_materials", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                 H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, table);
    H5Dclose(set), H5Sclose(space);
    const hid_t version = H5Aopen(f, "version", H5P_DEFAULT);
    const long long five = 5;
    H5Awrite(version, H5T_NATIVE_LLONG, &five);
    H5Aclose(version), H5Fclose(f);
  }
  const TransportReader t(path);
  EXPECT_TRUE(t.header().lamps.tangent.empty());
  EXPECT_EQ(openRelightSource(path).relightLocal({parseLocalLight("point:0.3,1,0.2,3")},
                                                 kAnchorSpreadTexels, LampMode::Exact),
            before);
  try {
    requireAovs(t.header(), {Aov::Tangent}, path, false);
    FAIL() << "the tangent label of a version 5 file";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("tangent"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("run precompute again"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace acpca
