// The nine-coefficient SH lighting labels: closed forms, an independent
// projection of the lattice's radiance on a fine lat-long grid, and rotation.
#include "lighting/sh_lighting.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lighting/lighting.h"
#include "lighting/rotation.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(ShLighting, TheBasisIsTheUsualPolynomialsInOurAxes) {
  const Vec3 d = Vec3(0.48, -0.6, 0.64).normalized();
  const auto y = realSh9(d);
  EXPECT_NEAR(y[0], 0.5 / std::sqrt(kPi), 1e-15);
  EXPECT_NEAR(y[1], std::sqrt(3 / (4 * kPi)) * d.y(), 1e-15);
  EXPECT_NEAR(y[2], std::sqrt(3 / (4 * kPi)) * d.z(), 1e-15);
  EXPECT_NEAR(y[3], std::sqrt(3 / (4 * kPi)) * d.x(), 1e-15);
  EXPECT_NEAR(y[4], std::sqrt(15 / (4 * kPi)) * d.x() * d.y(), 1e-15);
  EXPECT_NEAR(y[6], std::sqrt(5 / (16 * kPi)) * (3 * d.z() * d.z() - 1), 1e-15);
  EXPECT_NEAR(y[8], std::sqrt(15 / (16 * kPi)) * (d.x() * d.x() - d.y() * d.y()), 1e-15);
}

TEST(ShLighting, EachTexelsMeanIsItsCellsBandsWeightedByTheirSolidAngles) {
  // The projector sums each texel from one face's moments turned onto the
  // others; here each texel's 16 x 16 cells are summed directly instead.
  const CubeLattice lattice(6);
  const ShProjector sh(lattice);
  const int r = lattice.resolution(), kCells = 16;
  const double cell = 2.0 / r / kCells;
  for (int texel = 0; texel < lattice.size(); ++texel) {
    const TexelCoord t = lattice.texelCoord(texel);
    std::array<double, 9> sum{};
    double area = 0;
    for (int i = 0; i < kCells; ++i)
      for (int k = 0; k < kCells; ++k) {
        const double s0 = -1 + (t.col * kCells + k) * cell, t0 = -1 + (t.row * kCells + i) * cell;
        const double w = CubeLattice::rectangleSolidAngle(s0, t0, s0 + cell, t0 + cell);
        const auto y = realSh9(
            CubeLattice::faceDirection(t.face, s0 + 0.5 * cell, t0 + 0.5 * cell).normalized());
        for (int b = 0; b < 9; ++b) sum[b] += w * y[b];
        area += w;
      }
    LatticeLighting oneTexel(3 * lattice.size(), 0.0);
    oneTexel[3 * texel] = 1;  // red alone
    const auto got = sh.project(oneTexel);
    for (int b = 0; b < 9; ++b) {
      EXPECT_NEAR(got[b].x(), sum[b] / area, 1e-14) << "texel " << texel << " band " << b;
      EXPECT_EQ(got[b].y(), 0);
    }
  }
}

TEST(ShLighting, AConstantMapHasOnlyItsClosedFormBandZero) {
  const CubeLattice lattice(8);
  const ShProjector sh(lattice);
  const auto c = sh.project(computeLighting(*loadEnvironment("constant:1,2,3"), lattice, {}));
  for (int ch = 0; ch < 3; ++ch) {
    // The integral of (ch + 1) Y00 over the sphere: (ch + 1) 4 pi / (2 sqrt(pi)).
    EXPECT_NEAR(c[0][ch], (ch + 1) * 2 * std::sqrt(kPi), 1e-9);
    for (int b = 1; b < 9; ++b) EXPECT_NEAR(c[b][ch], 0, 1e-9) << b;
  }
}

/// The same coefficients another way: the lattice's radiance (each texel's
/// lighting over its solid angle) looked up per cell of a 2048 x 1024
/// lat-long grid, times Y at the cell's centre and its solid angle.
std::array<Rgb, 9> projectOnLatLong(const CubeLattice& lattice, const LatticeLighting& lighting) {
  std::array<Rgb, 9> out;
  out.fill(Rgb::Zero());
  const int width = 2048, height = 1024;
  for (int i = 0; i < height; ++i) {
    const double theta0 = kPi * i / height, theta1 = kPi * (i + 1) / height;
    const double theta = 0.5 * (theta0 + theta1);
    const double cell = (std::cos(theta0) - std::cos(theta1)) * 2 * kPi / width;
    for (int k = 0; k < width; ++k) {
      const double phi = 2 * kPi * (k + 0.5) / width;
      const Vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi));
      const int t = lattice.texelOf(d);
      const Rgb radiance =
          Rgb(lighting[3 * t], lighting[3 * t + 1], lighting[3 * t + 2]) / lattice.solidAngle(t);
      const auto y = realSh9(d);
      for (int b = 0; b < 9; ++b) out[b] += cell * y[b] * radiance;
    }
  }
  return out;
}

TEST(ShLighting, MapsAndSunsMatchAnIndependentProjectionOfTheLattice) {
  const CubeLattice lattice(16);
  const ShProjector sh(lattice);
  for (const char* spec : {"sky", "sun:50,30,4,1000", "sun:-20,200,2,3000"}) {
    const LatticeLighting lighting = computeLighting(*loadEnvironment(spec), lattice, {});
    const auto ours = sh.project(lighting), theirs = projectOnLatLong(lattice, lighting);
    const double scale = ours[0].norm();
    double worst = 0;
    for (int b = 0; b < 9; ++b) {
      EXPECT_LT((ours[b] - theirs[b]).norm(), 2e-3 * scale) << spec << " coefficient " << b;
      worst = std::max(worst, (ours[b] - theirs[b]).norm() / scale);
    }
    RecordProperty(std::string("worst_relative_to_band_0 ") + spec, std::to_string(worst));
  }
}

TEST(ShLighting, ARotatedMapHasRotatedCoefficientsWithinTheLatticesBinning) {
  // Band 1 is the dipole D = integral of L w: (Y(1,-1), Y(1,0), Y(1,1)) ~
  // (D_y, D_z, D_x); band 2 holds the quadratic form M = integral of L w w^T.
  // A map rotated by R has R D and R M R^T.
  const CubeLattice lattice(32);
  const ShProjector sh(lattice);
  const auto dipole = [](const std::array<Rgb, 9>& c) {
    return Vec3(c[3].x(), c[1].x(), c[2].x());
  };
  for (const EnvRotation& r :
       {EnvRotation{90, 0, 0}, EnvRotation{0, 90, 0}, EnvRotation{35, 20, 0}}) {
    const auto sun = loadEnvironment("sun:40,60,6,1000");
    const auto plain = sh.project(computeLighting(*sun, lattice, {}));
    const auto turned = sh.project(computeLighting(*sun, lattice, r));
    EXPECT_NEAR(turned[0].x(), plain[0].x(), 1e-3 * plain[0].x()) << "energy";
    const Vec3 expected = rotationMatrix(r) * dipole(plain);
    EXPECT_LT((dipole(turned) - expected).norm(), 0.01 * expected.norm())
        << r.label() << ": " << dipole(turned).transpose() << " against " << expected.transpose();
    RecordProperty("dipole_error " + r.label(),
                   std::to_string((dipole(turned) - expected).norm() / expected.norm()));
  }
}

}  // namespace
}  // namespace acpca
