// The dimensionality analysis: power-law fits recover known exponents, patch
// dimensionality counts the rank of synthetic rows, square patches read the
// right rows, and mu / p* follow sec. 5.1 and eq. 27.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cluster/dimensionality.h"
#include "model/cost_model.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

TEST(PowerLawFit, RecoversKnownExponents) {
  for (double slope : {0.5, 0.9, 1.0, 1.3}) {
    std::vector<double> x, y;
    for (double a = 16; a <= 4096; a *= 1.5) x.push_back(a), y.push_back(3.5 * std::pow(a, slope));
    const PowerLaw fit = fitPowerLaw(x, y);
    EXPECT_NEAR(fit.slope, slope, 1e-10);
    EXPECT_NEAR(fit.scale, 3.5, 1e-8);
    EXPECT_EQ(fit.points, static_cast<int>(x.size()));
  }
  // Multiplicative noise of +-10% moves the slope only a little over 2.4 decades.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(0.9, 1.1);
  std::vector<double> x, y;
  for (double a = 16; a <= 4096; a *= 1.2)
    x.push_back(a), y.push_back(2 * std::sqrt(a) * noise(rng));
  EXPECT_NEAR(fitPowerLaw(x, y).slope, 0.5, 0.03);
  // Non-positive points are ignored; one point cannot fix a slope.
  EXPECT_NEAR(fitPowerLaw({0, 10, 100, -1}, {5, 10, 100, 7}).slope, 1.0, 1e-12);
  EXPECT_TRUE(std::isnan(fitPowerLaw({10}, {3}).slope));
  EXPECT_TRUE(std::isnan(fitPowerLaw({10, 10}, {3, 4}).slope));
}

TEST(PowerLawFit, MuAndOptimalPatchSizeFollowTheirDefinitions) {
  EXPECT_NEAR(muFromSlope(1.0, 4), 0.25, 1e-15);
  EXPECT_NEAR(muFromSlope(0.5, 4), 0.5, 1e-15);
  EXPECT_NEAR(muFromSlope(0.5, 2), std::sqrt(0.5), 1e-15);
  // [Mahajan07] sec. 4.3: mu = 0.68, r = 2, N = 150 puts p* near N.
  EXPECT_NEAR(optimalPatchSize(0.68, 2, 150), 150 * 0.36 / 0.32, 1e-9);
  // eq. 26 holds at p*: d = 0.
  const double p = optimalPatchSize(0.3, 4, 700);
  EXPECT_NEAR(subdivisionMetric(0.3, 4, 10, static_cast<long long>(std::llround(p)), 700), 0, 20);
}

TEST(PatchDimensionality, CountsTheRankOfSyntheticRows) {
  const int l = 40;
  std::mt19937 rng(5);
  std::normal_distribution<float> gauss;
  for (int rank : {1, 3, 7}) {
    for (long long rows : {5LL, 30LL, 100LL}) {  // fewer and more rows than l
      std::vector<float> basis(static_cast<size_t>(rank) * l), coefficient(rank);
      for (auto& v : basis) v = gauss(rng);
      PatchRows patch;
      patch.rows = rows;
      patch.values.assign(static_cast<size_t>(rows) * l, 0.0f);
      for (long long r = 0; r < rows; ++r) {
        for (auto& c : coefficient) c = gauss(rng);
        for (int k = 0; k < rank; ++k)
          for (int j = 0; j < l; ++j) patch.values[r * l + j] += coefficient[k] * basis[k * l + j];
      }
      const int expected = static_cast<int>(std::min<long long>(rank, rows));
      EXPECT_EQ(patchDimensionality(patch, l, 1.0), expected) << rank << " " << rows;
      EXPECT_LE(patchDimensionality(patch, l, 0.9), expected);
    }
  }
  EXPECT_EQ(patchDimensionality(PatchRows{}, l, 0.9995), 0);
}

class SquarePatch : public test::SmallPlantSuite {};

TEST_F(SquarePatch, ReadsTheOccupiedPixelsOfTheSquareClippedToTheImage) {
  const TransportReader transport(path());
  const TransportHeader& h = transport.header();
  const int l = transport.latticeSize();
  std::vector<float> row(l);
  for (auto [cx, cy, side] : {std::tuple{20, 20, 8}, {0, 0, 6}, {39, 39, 64}, {10, 30, 1}}) {
    const PatchRows patch = readSquarePatch(transport, cx, cy, side);
    long long expected = 0;
    for (int y = cy - side / 2; y < cy - side / 2 + side; ++y)
      for (int x = cx - side / 2; x < cx - side / 2 + side; ++x) {
        if (x < 0 || y < 0 || x >= 40 || y >= 40) continue;
        const long long r = test::rowOfPixel(h, x, y);
        if (r < 0) continue;
        // Rows come in image order: the expected-th row of the patch is this pixel's row.
        transport.readRows(r, 1, row.data());
        ASSERT_LT(expected, patch.rows);
        for (int j = 0; j < l; ++j) ASSERT_EQ(patch.values[expected * l + j], row[j]);
        ++expected;
      }
    EXPECT_EQ(patch.rows, expected) << cx << "," << cy << " side " << side;
  }
}

}  // namespace
}  // namespace acpca
