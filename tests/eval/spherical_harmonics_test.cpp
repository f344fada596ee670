// Spherical harmonics and [Lam06]'s fits: orthonormal functions with the
// textbook closed forms; on a hemisphere the Gram matrix is ill-conditioned and
// plain least squares blows the coefficients up, while CLS and CEB keep them
// within the energy bound at a small cost in residual; the transport baseline
// covers every lit texel and stores coefficients as the paper does.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>

#include "eval/error_measures.h"
#include "eval/sh_transport.h"
#include "eval/spherical_harmonics.h"
#include "lighting/lighting.h"
#include "relight/dense_relight.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

TEST(SphericalHarmonics, MatchTheClosedFormsOfTheFirstBands) {
  const double c0 = 0.5 / std::sqrt(M_PI), c1 = std::sqrt(3 / (4 * M_PI));
  for (const Vec3& d : {Vec3(0, 0, 1), Vec3(0.6, 0, 0.8), Vec3(0.48, -0.6, 0.64)}) {
    double y[9];
    evaluateSh(3, d, y);
    EXPECT_NEAR(y[0], c0, 1e-12);
    // Up to the Condon-Shortley sign, band 1 is (y, z, x) times sqrt(3 / 4 pi).
    EXPECT_NEAR(std::abs(y[1]), c1 * std::abs(d.y()), 1e-12);
    EXPECT_NEAR(y[2], c1 * d.z(), 1e-12);
    EXPECT_NEAR(std::abs(y[3]), c1 * std::abs(d.x()), 1e-12);
    EXPECT_NEAR(y[6], std::sqrt(5 / (16 * M_PI)) * (3 * d.z() * d.z() - 1), 1e-12);
    EXPECT_NEAR(std::abs(y[8]),
                std::sqrt(15 / (16 * M_PI)) * std::abs(d.x() * d.x() - d.y() * d.y()), 1e-12);
  }
}

TEST(SphericalHarmonics, AreOrthonormalOverTheLattice) {
  const CubeLattice lattice(48);
  const Eigen::MatrixXd y = shOnLattice(lattice, 8);
  Eigen::MatrixXd weighted = y;
  for (int j = 0; j < lattice.size(); ++j) weighted.row(j) *= lattice.solidAngle(j);
  const Eigen::MatrixXd gram = y.transpose() * weighted;
  // Texel-centre quadrature of degree-14 polynomials on a 6x48x48 lattice.
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(64, 64)).cwiseAbs().maxCoeff(), 2e-3);
  EXPECT_THROW(shBandsOf(50, "--sh-orders"), UserError);
  EXPECT_EQ(shBandsOf(49, "--sh-orders"), 7);
}

/// The Gram matrix over the texels of the upper (+Z) hemisphere and those texels.
struct Hemisphere {
  CubeLattice lattice{16};
  std::vector<int> texels;
  Eigen::MatrixXd y, gram;
  explicit Hemisphere(int bands) {
    const Eigen::MatrixXd all = shOnLattice(lattice, bands);
    for (int j = 0; j < lattice.size(); ++j)
      if (lattice.direction(j).z() > 0) texels.push_back(j);
    y.resize(texels.size(), all.cols());
    for (size_t k = 0; k < texels.size(); ++k) y.row(k) = all.row(texels[k]);
    gram = y.transpose() * weights().asDiagonal() * y;
  }
  Eigen::VectorXd weights() const {
    Eigen::VectorXd w(texels.size());
    for (size_t k = 0; k < texels.size(); ++k) w[k] = lattice.solidAngle(texels[k]);
    return w;
  }
  /// b = Y^T W f and the energy of f given on the hemisphere's texels.
  std::pair<Eigen::VectorXd, double> project(const Eigen::VectorXd& f) const {
    const Eigen::VectorXd wf = weights().cwiseProduct(f);
    return {y.transpose() * wf, f.dot(wf)};
  }
  double residual(const Eigen::VectorXd& f, const Eigen::VectorXd& c) const {
    const Eigen::VectorXd r = f - y * c;
    return r.dot(weights().cwiseProduct(r));
  }
};

TEST(ShFits, RecoverAFunctionInTheSpanExactly) {
  const Hemisphere h(4);
  const ShSupportFit fit(h.gram);
  EXPECT_NEAR(h.gram.trace() / 16, 0.5, 0.01) << "kappa = 1/2 on a hemisphere";
  std::mt19937 rng(3);
  std::normal_distribution<double> gauss;
  Eigen::VectorXd truth(16);
  for (auto& v : truth) v = gauss(rng) * 0.1;
  const Eigen::VectorXd f = h.y * truth;
  const auto [b, energy] = h.project(f);
  Eigen::VectorXd c(16);
  fit.fit(ShFit::Uls, b.data(), energy, c.data());
  EXPECT_LT((c - truth).norm(), 1e-8 * truth.norm());
}

TEST(ShFits, HemisphereIsIllConditionedAndUlsBlowsUpWhileClsAndCebHoldTheBound) {
  double previousCondition = 1;
  for (int bands : {4, 5, 7, 8}) {
    const Hemisphere h(bands);
    const ShSupportFit fit(h.gram);
    EXPECT_GT(fit.conditionNumber(), previousCondition) << bands << " bands";
    previousCondition = fit.conditionNumber();
    // A shadowed cosine lobe: the kind of function a transport row holds.
    Eigen::VectorXd f(h.texels.size());
    for (size_t k = 0; k < h.texels.size(); ++k) {
      const Vec3& d = h.lattice.direction(h.texels[k]);
      f[k] = (d.x() > 0.3 && d.y() < 0.2) ? 0.0 : d.z();
    }
    const auto [b, energy] = h.project(f);
    const int n = bands * bands;
    Eigen::VectorXd uls(n), cls(n), ceb(n);
    double lambda = -1;
    fit.fit(ShFit::Uls, b.data(), energy, uls.data());
    fit.fit(ShFit::Cls, b.data(), energy, cls.data(), &lambda);
    fit.fit(ShFit::Ceb, b.data(), energy, ceb.data());
    const double bound = fit.coefficientBound(energy);
    EXPECT_LE(cls.squaredNorm(), bound * (1 + 1e-9)) << n;
    EXPECT_LE(ceb.squaredNorm(), bound * (1 + 1e-9)) << n;
    // CLS is the least-squares optimum under the bound: no worse than CEB, and
    // unconstrained least squares is the best of all.
    EXPECT_LE(h.residual(f, cls), h.residual(f, ceb) * (1 + 1e-9)) << n;
    EXPECT_LE(h.residual(f, uls), h.residual(f, cls) * (1 + 1e-9)) << n;
    if (bands >= 7) {
      EXPECT_GT(fit.conditionNumber(), 1e3) << n;
      EXPECT_GT(uls.squaredNorm(), 10 * bound) << n;
      // The smallest ridge: a little less breaks the bound (eq. 21).
      ASSERT_GT(lambda, 0) << n;
      const Eigen::VectorXd looser =
          (h.gram + 0.99 * lambda * Eigen::MatrixXd::Identity(n, n)).ldlt().solve(b);
      EXPECT_GT(looser.squaredNorm(), bound) << n;
      EXPECT_NEAR(cls.squaredNorm(), bound, 1e-6 * bound) << n;
    }
  }
}

TEST(ShFits, ZeroFunctionGivesZeroCoefficients) {
  const Hemisphere h(7);
  const ShSupportFit fit(h.gram);
  const Eigen::VectorXd b = Eigen::VectorXd::Zero(49);
  for (ShFit f : {ShFit::Uls, ShFit::Cls, ShFit::Ceb}) {
    Eigen::VectorXd c = Eigen::VectorXd::Constant(49, 7.0);
    fit.fit(f, b.data(), 0.0, c.data());
    EXPECT_EQ(c.norm(), 0.0) << shFitName(f);
  }
}

class ShTransportTest : public test::SmallPlantSuite {};

TEST_F(ShTransportTest, SupportsHoldEveryLitTexelAndOnlyUlsSuffersFromEightBits) {
  const TransportReader transport(path());
  ShTransport sh(transport, 49, 4);
  std::vector<float> rows(transport.rows() * transport.latticeSize());
  transport.readRows(0, transport.rows(), rows.data());
  // A group's support is at least its normal's hemisphere and holds every
  // texel its rows light.
  std::vector<std::vector<char>> inSupport(sh.groups());
  for (int g = 0; g < sh.groups(); ++g) {
    inSupport[g].assign(transport.latticeSize(), 0);
    for (int j : sh.support(g)) inSupport[g][j] = 1;
    EXPECT_GE(sh.support(g).size(), size_t(transport.latticeSize() / 2 - 8));
    EXPECT_LT(sh.support(g).size(), size_t(transport.latticeSize()));
  }
  long long lit = 0;
  for (long long p = 0; p < transport.rows(); ++p)
    for (int j = 0; j < transport.latticeSize(); ++j)
      if (rows[p * transport.latticeSize() + j] != 0) {
        ++lit;
        ASSERT_TRUE(inSupport[sh.groupOfRow(p)][j]) << "row " << p << " texel " << j;
      }
  EXPECT_GT(lit, transport.rows() * 10);

  const CubeLattice lattice(transport.header().cubemapResolution);
  const LatticeLighting sky = computeLighting(*loadEnvironment("sky"), lattice, {});
  const auto truth = denseRelight(transport, {sky});
  std::vector<float> image(3 * transport.rows());
  for (ShFit f : {ShFit::Uls, ShFit::Cls, ShFit::Ceb}) {
    ShCoefficients c = sh.fit(49, f);
    sh.relight(c, sky, image.data());
    for (float v : image) ASSERT_TRUE(std::isfinite(v));
    // A 7-band fit of leaf-shadowed rows: an approximation, not a wreck.
    EXPECT_LT(relativeL2(image, truth[0]), 0.15) << shFitName(f);
    const ShStatistics s = sh.statistics(c);
    if (f != ShFit::Uls) {
      EXPECT_LE(s.maxNormToBound, 1 + 1e-5) << shFitName(f);
    }
    if (f == ShFit::Uls) {
      EXPECT_GT(s.maxNormToBound, 10) << "ULS on hemispheres exceeds the energy bound";
      EXPECT_GT(s.medianCondition, 1e4);
    }
    const double exactError = relativeL2(image, truth[0]);
    // i8: every coefficient within half a step of its map's scale.
    const ShCoefficients exact = c;
    storeShCoefficients(c, CoeffPrecision::I8);
    for (int i = 0; i < c.n; ++i) {
      float largest = 0;
      for (long long p = 0; p < transport.rows(); ++p)
        largest = std::max(largest, std::abs(exact.values[p * c.n + i]));
      for (long long p = 0; p < transport.rows(); ++p)
        ASSERT_LE(std::abs(c.values[p * c.n + i] - exact.values[p * c.n + i]),
                  0.5f * largest / 127 * 1.0001f);
    }
    // [Lam06]'s result: 8-bit maps wreck ULS but cost CLS and CEB next to nothing.
    sh.relight(c, sky, image.data());
    const double quantizedError = relativeL2(image, truth[0]);
    if (f == ShFit::Uls)
      EXPECT_GT(quantizedError, 1.5 * exactError);
    else
      EXPECT_LT(quantizedError, 1.05 * exactError) << shFitName(f);
  }
  EXPECT_GT(sh.costPerPixel(49), 49);
}

TEST_F(ShTransportTest, SameCoefficientsAndImageWithOneOrTwoThreads) {
  const TransportReader transport(path());
  const CubeLattice lattice(transport.header().cubemapResolution);
  const LatticeLighting sun = computeLighting(*loadEnvironment("sun:50,30,8,1000"), lattice, {});
  const auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    ShTransport sh(transport, 25, 4);
    const ShCoefficients c = sh.fit(25, ShFit::Cls);
    std::vector<float> image(3 * transport.rows());
    sh.relight(c, sun, image.data());
    return std::make_pair(c.values, image);
  };
  EXPECT_EQ(run(1), run(2));
}

TEST(ShTransport, RgbRowsFitEachChannelAsItsOwnTransport) {
  // Channel c of the bounced plant's SH relight equals the SH relight of a
  // transport holding only channel c's rows.
  const TransportReader rgb(test::fixture("bounced-plant"));
  ASSERT_EQ(rgb.header().channels, 3);
  const int l = rgb.latticeSize();
  std::vector<float> rows(static_cast<size_t>(rgb.rows()) * 3 * l);
  rgb.readRows(0, rgb.rows(), rows.data());
  const CubeLattice lattice(rgb.header().cubemapResolution);
  const LatticeLighting sky = computeLighting(*loadEnvironment("sky"), lattice, {});
  ShTransport sh(rgb, 25, 4);
  std::vector<float> image(3 * rgb.rows());
  sh.relight(sh.fit(25, ShFit::Cls), sky, image.data());
  EXPECT_GT(sh.costPerPixel(25), 25);
  test::TempDir dir;
  for (int c = 0; c < 3; ++c) {
    TransportHeader header = rgb.header();
    header.channels = 1;
    header.bounces = 0;
    std::vector<float> part(static_cast<size_t>(rgb.rows()) * l);
    for (long long r = 0; r < rgb.rows(); ++r)
      std::copy_n(rows.data() + (r * 3 + c) * l, l, part.data() + r * l);
    const std::string path = dir.file(concat("channel", c, ".h5"));
    {
      TransportWriter writer(path, header);
      writer.writeRows(0, rgb.rows(), part.data());
      writer.finish();
    }
    const TransportReader one(path);
    ShTransport shOne(one, 25, 4);
    std::vector<float> alone(3 * rgb.rows());
    shOne.relight(shOne.fit(25, ShFit::Cls), sky, alone.data());
    for (long long r = 0; r < rgb.rows(); ++r) ASSERT_EQ(image[3 * r + c], alone[3 * r + c]) << r;
  }
}

}  // namespace
}  // namespace acpca
