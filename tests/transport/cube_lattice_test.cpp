#include "transport/cube_lattice.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/error.h"

namespace acpca {
namespace {

struct WorkedVector {
  Vec3 direction;
  int face, row, col, texel;
};

// docs/design.md section 3, at R = 32: pinned literally.
TEST(CubeLattice, WorkedVectorsOfTheDesignMapLiterally) {
  const CubeLattice lattice(32);
  const WorkedVector cases[] = {{{1, 0.5, -0.25}, 0, 8, 20, 276},
                                {{0, 1, 0}, 2, 16, 16, 2576},
                                {{0.2, -0.3, -1}, 5, 20, 12, 5772},
                                {{-1, 0.1, 0.3}, 1, 14, 20, 1492}};
  for (const auto& c : cases) {
    const int j = lattice.texelOf(c.direction);
    EXPECT_EQ(j, c.texel) << c.direction.transpose();
    const TexelCoord coord = lattice.texelCoord(j);
    EXPECT_EQ(coord.face, c.face);
    EXPECT_EQ(coord.row, c.row);
    EXPECT_EQ(coord.col, c.col);
    EXPECT_EQ(lattice.texelIndex({c.face, c.row, c.col}), c.texel);
  }
}

TEST(CubeLattice, FaceOrderAndMajorAxes) {
  const CubeLattice lattice(8);
  const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int f = 0; f < 6; ++f) EXPECT_EQ(lattice.texelCoord(lattice.texelOf(axes[f])).face, f);
}

TEST(CubeLattice, TexelCentresMapBackToTheirTexel) {
  for (int r : {1, 2, 7, 16, 32}) {
    const CubeLattice lattice(r);
    for (int j = 0; j < lattice.size(); ++j) {
      ASSERT_EQ(lattice.texelOf(lattice.direction(j)), j) << "R " << r;
      ASSERT_NEAR(lattice.direction(j).norm(), 1.0, 1e-12);
    }
  }
}

TEST(CubeLattice, SolidAnglesSumToFourPi) {
  for (int r : {1, 4, 16, 32, 64}) {
    const CubeLattice lattice(r);
    double sum = 0;
    for (double w : lattice.solidAngles()) sum += w;
    EXPECT_NEAR(sum / (4 * std::numbers::pi), 1.0, 1e-6) << "R " << r;
  }
}

TEST(CubeLattice, SolidAnglesAreExactNotUniform) {
  const CubeLattice lattice(32);
  const double corner = lattice.solidAngle(lattice.texelIndex({4, 0, 0}));
  const double centre = lattice.solidAngle(lattice.texelIndex({4, 16, 16}));
  // Corner texels are about 5x smaller than centre ones at R = 32 (ratio -> 3^1.5).
  EXPECT_GT(centre / corner, 4.5);
  EXPECT_LT(centre / corner, 5.3);
  // A texel's solid angle matches a Monte Carlo estimate of its footprint.
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  const int samples = 2000000;
  std::vector<int> hits(lattice.size(), 0);
  for (int i = 0; i < samples; ++i)
    ++hits[lattice.texelOf(Vec3(normal(rng), normal(rng), normal(rng)))];
  for (int j : {lattice.texelIndex({4, 0, 0}), lattice.texelIndex({4, 16, 16})}) {
    const double estimate = 4 * std::numbers::pi * hits[j] / samples;
    EXPECT_NEAR(estimate / lattice.solidAngle(j), 1.0, 0.12);
  }
}

TEST(CubeLattice, BilinearReproducesTexelCentresAndIsContinuousAcrossSeams) {
  const CubeLattice lattice(16);
  // A smooth function sampled at texel centres.
  auto f = [](const Vec3& d) { return 1 + d.x() + 2 * d.y() + 3 * d.z(); };
  std::vector<double> values(lattice.size());
  for (int j = 0; j < lattice.size(); ++j) values[j] = f(lattice.direction(j));
  for (int j = 0; j < lattice.size(); j += 37)
    EXPECT_NEAR(lattice.bilinear(values, lattice.direction(j)), values[j], 1e-9);
  // Weights form a partition of unity.
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 1000; ++i) {
    double sum = 0;
    for (const auto& tap : lattice.bilinearTaps(Vec3(normal(rng), normal(rng), normal(rng))))
      sum += tap.weight;
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
  // Walk across every edge of face +Z: the lookup has no jump at the seam.
  const double eps = 1e-7;
  for (double a = -0.95; a <= 0.95; a += 0.05) {
    const Vec3 edges[4][2] = {{{1 + eps, a, 1}, {1 - eps, a, 1}},
                              {{-1 - eps, a, 1}, {-1 + eps, a, 1}},
                              {{a, 1 + eps, 1}, {a, 1 - eps, 1}},
                              {{a, -1 - eps, 1}, {a, -1 + eps, 1}}};
    for (const auto& e : edges) {
      const double across = lattice.bilinear(values, e[0]) - lattice.bilinear(values, e[1]);
      EXPECT_NEAR(across, 0.0, 1e-3) << "at " << e[0].transpose();
      // And the lookup stays close to the function it interpolates.
      EXPECT_NEAR(lattice.bilinear(values, e[0]), f(e[0].normalized()), 0.05);
    }
  }
}

TEST(CubeLattice, TexelsOfManyDirectionsEqualTexelOfEach) {
  // Random directions, then the cases where a select could differ from a
  // branch: ties between axes, signed zeros, face edges and corners.
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  std::vector<Vec3> dirs;
  for (int i = 0; i < 20000; ++i) dirs.emplace_back(normal(rng), normal(rng), normal(rng));
  for (double a : {-1.0, -0.0, 0.0, 0.5, 1.0})
    for (double b : {-1.0, -0.0, 0.0, 0.5, 1.0})
      for (double c : {-1.0, -0.0, 0.0, 0.5, 1.0})
        if (a != 0 || b != 0 || c != 0) dirs.emplace_back(a, b, c);
  for (int r : {1, 7, 32}) {
    const CubeLattice lattice(r);
    // Texel boundaries in face coordinates, 2 k / R - 1, sit exactly on an edge.
    for (int k = 0; k <= r; ++k) dirs.emplace_back(1.0, 2.0 * k / r - 1, 0.25);
    std::vector<double> x, y, z;
    for (const Vec3& d : dirs) x.push_back(d.x()), y.push_back(d.y()), z.push_back(d.z());
    std::vector<int> texels(dirs.size(), -1);
    lattice.texelsOf(x.data(), y.data(), z.data(), static_cast<int>(dirs.size()), texels.data());
    for (size_t i = 0; i < dirs.size(); ++i)
      ASSERT_EQ(texels[i], lattice.texelOf(dirs[i])) << "R " << r << " " << dirs[i].transpose();
  }
  const CubeLattice lattice(8);
  const double zero = 0, nan = std::nan("");
  int texel;
  EXPECT_ANY_THROW(lattice.texelsOf(&zero, &zero, &zero, 1, &texel));
  EXPECT_ANY_THROW(lattice.texelsOf(&nan, &zero, &zero, 1, &texel));
}

TEST(CubeLattice, RefusesBadResolutions) {
  EXPECT_THROW(CubeLattice(0), UserError);
  EXPECT_THROW(CubeLattice(-3), UserError);
  EXPECT_THROW(CubeLattice(CubeLattice::kMaxResolution + 1), UserError);
}

}  // namespace
}  // namespace acpca
