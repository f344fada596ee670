#include "cluster/pca.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <random>

#include "cluster/symmetric_eigen.h"

namespace acpca {
namespace {

Eigen::MatrixXd lowRank(int rows, int cols, int rank, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n;
  Eigen::MatrixXd a(rows, rank), b(rank, cols);
  for (int i = 0; i < a.size(); ++i) a.data()[i] = n(rng);
  for (int i = 0; i < b.size(); ++i) b.data()[i] = n(rng);
  return a * b;
}

TEST(Pca, RecoversTheRankOfLowRankDataAndReconstructsIt) {
  for (auto [rows, cols] : {std::pair{40, 100}, std::pair{100, 40}}) {
    const Eigen::MatrixXd x = lowRank(rows, cols, 5, 1);
    const PcaResult pca = pcaToTolerance(x, 1.0, false);
    EXPECT_EQ(pca.rank, 5);
    const Eigen::MatrixXd back = x * pca.basis * pca.basis.transpose();
    EXPECT_LT((back - x).norm() / x.norm(), 1e-9);
    EXPECT_LT((pca.basis.transpose() * pca.basis - Eigen::MatrixXd::Identity(5, 5)).norm(), 1e-9);
  }
}

TEST(Pca, HonoursTheToleranceAndNeverExceedsIt) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n;
  Eigen::MatrixXd x(60, 30);
  for (int i = 0; i < x.size(); ++i) x.data()[i] = n(rng) * std::exp(-0.2 * (i % 30));
  int previous = 0;
  for (double tol : {0.5, 0.9, 0.99, 0.999}) {
    const PcaResult pca = pcaToTolerance(x, tol, false);
    const Eigen::MatrixXd residual = x - x * pca.basis * pca.basis.transpose();
    EXPECT_LE(residual.squaredNorm(), (1 - tol) * x.squaredNorm() * (1 + 1e-9));
    EXPECT_NEAR(residual.squaredNorm(), pca.residualEnergy, 1e-8 * x.squaredNorm());
    EXPECT_GE(pca.rank, previous);
    previous = pca.rank;
  }
}

TEST(Pca, TheFloatRankMatchesTheDoubleRankForEitherGramShape) {
  // Decaying spectrum on top of a large common row (a mean most of the energy,
  // as transport has): the float path centres before it multiplies.
  std::mt19937 rng(8);
  std::normal_distribution<double> n;
  for (auto [rows, cols] : {std::pair{50, 120}, std::pair{300, 60}}) {
    Eigen::MatrixXd x(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) x(i, j) = 100 + n(rng) * std::exp(-0.15 * j);
    for (bool mean : {false, true})
      for (double tol : {0.9, 0.99, 0.999}) {
        const int exact = pcaToTolerance(x, tol, mean, false).rank;
        EXPECT_NEAR(rankToTolerance(x.cast<float>(), tol, mean), exact, 1)
            << rows << "x" << cols << " mean " << mean << " tolerance " << tol;
        EXPECT_GT(exact, mean ? 5 : 0);
      }
  }
  EXPECT_EQ(rankToTolerance(Eigen::MatrixXf::Zero(4, 9), 0.99, true), 0);
  EXPECT_EQ(rankToTolerance(lowRank(30, 20, 3, 2).cast<float>(), 1.0, false), 3);
}

TEST(Pca, TheSmallerGramIsTheSmallerProductAndExactlySymmetric) {
  for (auto [rows, cols] : {std::pair{20, 70}, std::pair{70, 20}, std::pair{33, 33}}) {
    const Eigen::MatrixXd x = lowRank(rows, cols, 15, 3);
    const Eigen::MatrixXd expected =
        rows < cols ? Eigen::MatrixXd(x * x.transpose()) : Eigen::MatrixXd(x.transpose() * x);
    const Eigen::MatrixXf gram = smallerGram(x.cast<float>());
    ASSERT_EQ(gram.rows(), std::min(rows, cols));
    ASSERT_EQ(gram.cols(), std::min(rows, cols));
    EXPECT_LT((gram.cast<double>() - expected).norm(), 1e-5 * expected.norm());
    EXPECT_EQ(gram, gram.transpose());  // the upper triangle mirrors the lower
  }
}

TEST(SymmetricEigen, TheSolveAloneDecomposesAndIgnoresTheThreadCount) {
  // A Gram matrix large enough for OpenBLAS to split the work between threads.
  const Eigen::MatrixXd x = lowRank(300, 400, 250, 5);
  const Eigen::MatrixXd gram = x.transpose() * x;
  const SymmetricEigen alone = symmetricEigenAlone(gram, true);
  const SymmetricEigen one = symmetricEigen(gram, true);
  ASSERT_EQ(alone.vectors.cols(), 400);
  // A V = V diag(values), V orthonormal, the values those of the one-thread solve.
  const double scale = alone.values[0];
  EXPECT_LT((gram * alone.vectors - alone.vectors * alone.values.asDiagonal()).norm(),
            1e-11 * scale * 400);
  EXPECT_LT((alone.vectors.transpose() * alone.vectors - Eigen::MatrixXd::Identity(400, 400))
                .cwiseAbs()
                .maxCoeff(),
            1e-12 * 400);
  EXPECT_LT((alone.values - one.values).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_EQ((alone.values.array() > 1e-9 * scale).count(), 250);
  // Bit for bit the same under any TBB thread limit: the BLAS thread count
  // follows the machine, not --threads.
  for (int threads : {1, 2}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const SymmetricEigen again = symmetricEigenAlone(gram, true);
    EXPECT_EQ(again.values, alone.values) << threads;
    EXPECT_EQ(again.vectors, alone.vectors) << threads;
  }
}

TEST(Pca, AllZeroRowsGiveRankZero) {
  const PcaResult pca = pcaToTolerance(Eigen::MatrixXd::Zero(7, 12), 0.999, true);
  EXPECT_EQ(pca.rank, 0);
  EXPECT_EQ(pca.basis.cols(), 0);
  EXPECT_TRUE(pca.mean.allFinite());
}

}  // namespace
}  // namespace acpca
