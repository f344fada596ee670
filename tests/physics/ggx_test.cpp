// The GGX microfacet BRDF: its distribution is normalized, it is reciprocal,
// it loses energy only as single-scattering microfacet models must (more as
// it gets rougher, none in the smooth limit), and the precompute integrates
// it as a fine quadrature does.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "precompute/sampling_advice.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "tests/render_support.h"
#include "transport/material.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;

/// Directional albedo of the specular term alone: the integral over incoming
/// directions of ggxSpecular cos_i, by midpoint quadrature in (theta, phi).
double specularAlbedo(double cosO, double alpha, int steps = 600) {
  const Vec3 n(0, 0, 1), v(std::sqrt(1 - cosO * cosO), 0, cosO);
  double sum = 0;
  const double dTheta = 0.5 * kPi / steps, dPhi = 2 * kPi / (2 * steps);
  for (int i = 0; i < steps; ++i) {
    const double theta = (i + 0.5) * dTheta;
    for (int j = 0; j < 2 * steps; ++j) {
      const double phi = (j + 0.5) * dPhi;
      const Vec3 l(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                   std::cos(theta));
      const Vec3 h = (l + v).normalized();
      sum += ggxSpecular(l.z(), cosO, h.dot(n), alpha) * l.z() * std::sin(theta) * dTheta * dPhi;
    }
  }
  return sum;
}

TEST(Ggx, DistributionIntegratesToOneAgainstTheNormal) {
  for (double alpha : {0.05, 0.2, 0.5, 1.0}) {
    const int steps = 400000;
    double sum = 0;
    for (int i = 0; i < steps; ++i) {
      const double theta = (i + 0.5) * 0.5 * kPi / steps;
      sum += ggxDistribution(std::cos(theta), alpha) * std::cos(theta) * std::sin(theta);
    }
    EXPECT_NEAR(2 * kPi * sum * 0.5 * kPi / steps, 1.0, 1e-4) << alpha;
  }
}

TEST(Ggx, IsReciprocal) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  Material m{Material::Type::Ggx, {1, 1, 1}, 0.7, 1, 0.3};
  const Vec3 n(0, 1, 0);
  for (int k = 0; k < 1000; ++k) {
    Vec3 a(g(rng), std::abs(g(rng)), g(rng)), b(g(rng), std::abs(g(rng)), g(rng));
    a.normalize(), b.normalize();
    const Vec3 t(1, 0, 0);  // isotropic: any tangent
    const double ab = brdfShape(m, n, t, a, b), ba = brdfShape(m, n, t, b, a);
    EXPECT_NEAR(ab, ba, 1e-12 * std::max(1.0, ab));
    EXPECT_GE(ab, 0);
  }
}

TEST(Ggx, LosesEnergyOnlyAsASingleScatteringModelMust) {
  // White, no Fresnel: the directional albedo is at most 1 at every angle; the
  // missing part is light that bounces between microfacets, which grows with
  // roughness and vanishes in the smooth limit.
  double previous = 1;
  for (double alpha : {0.05, 0.25, 0.5, 1.0}) {
    const double normal = specularAlbedo(1.0, alpha);
    EXPECT_LE(normal, 1.0 + 1e-3) << alpha;
    EXPECT_LT(normal, previous + 1e-6) << alpha;
    previous = normal;
    for (double cosO : {0.2, 0.5, 0.8}) EXPECT_LE(specularAlbedo(cosO, alpha), 1.0 + 1e-3);
  }
  EXPECT_GT(specularAlbedo(1.0, 0.05), 0.99);
  // Closed form at alpha = 1 seen head-on: D = 1/pi, Lambda_o = 0 and
  // Lambda_i = (1/mu - 1)/2, so f = 1 / (2 pi (1 + mu)) and the albedo is
  // the integral of mu / (1 + mu) over [0, 1] = 1 - ln 2.
  EXPECT_NEAR(specularAlbedo(1.0, 1.0), 1 - std::log(2.0), 1e-4);
}

TEST(Ggx, ThePrecomputeIntegratesItAsAFineQuadratureDoes) {
  // A white GGX floor (ks = 1) seen from straight above under constant:1:
  // each pixel is the specular directional albedo at its view angle.
  for (double alpha : {0.3, 0.8}) {
    Scene s = test::floorScene(9, Material{Material::Type::Ggx, {1, 1, 1}, 1.0, 1, alpha});
    PrecomputeOptions o;
    o.cubemapResolution = 32;
    o.texelRays = 4;
    o.precision = Precision::F32;
    const auto t = test::precomputeInMemory(s, o);
    const CubeLattice lattice(32);
    const LatticeLighting L =
        computeLighting(*makeConstantEnvironment(Rgb::Constant(1)), lattice, {});
    const long long centre = test::rowOfPixel(t.header, 4, 4);
    ASSERT_GE(centre, 0);
    double value = 0;
    for (int j = 0; j < t.l; ++j) value += double(t.row(centre)[j]) * L[3 * j];
    const Vec3 toEye = (s.camera.eye - Vec3(0, 0, 0)).normalized();
    EXPECT_NEAR(value, specularAlbedo(toEye.y(), alpha), 0.01) << alpha;
  }
}

TEST(Ggx, NarrowLobesTheLatticeUnderSamplesAreWarnedOf) {
  Material m{Material::Type::Ggx, {1, 1, 1}, 1.0, 1, 0.02};
  // Half the light-direction width at half maximum is twice the half-normal angle.
  const double w = lobeHalfWidth(m);
  EXPECT_NEAR(ggxDistribution(std::cos(w / 2), 0.02), ggxDistribution(1.0, 0.02) / 2,
              1e-9 * ggxDistribution(1.0, 0.02));
  Scene s = makeBuiltinScene("sphere");
  s.spheres[0].material = m;
  PrecomputeOptions o;
  o.cubemapResolution = 32;
  const auto warnings = samplingWarnings(s, o);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("GGX roughness 0.02"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("rays per texel or a larger cube map"), std::string::npos)
      << warnings[0];
  s.spheres[0].material.roughness = 0.5;
  EXPECT_TRUE(samplingWarnings(s, o).empty());
}

}  // namespace
}  // namespace acpca
