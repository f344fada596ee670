// Every eigen-decomposition is checked before use (cluster/eigen_check.h): a
// sound one passes, a corrupted one is named, a wrong answer is solved again
// by Eigen, and two wrong answers end in a clear error, never a crash. The
// BLAS thread count changes while no other LAPACK call is in flight.
#include "cluster/eigen_check.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstdlib>
#include <limits>
#include <random>
#include <thread>

#include "cluster/blas_core.h"
#include "cluster/symmetric_eigen.h"
#include "core/error.h"
#include "core/warning.h"

namespace acpca {
namespace {

/// x^T x of a rows x n Gaussian x: positive semi-definite, rank min(rows, n).
template <typename Scalar>
SymmetricMatrix<Scalar> gram(int n, int rows, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd x(rows, n);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(rng);
  return (x.transpose() * x).cast<Scalar>();
}

template <typename Scalar>
EigenAnswer<Scalar> sound(const SymmetricMatrix<Scalar>& a, bool wantVectors) {
  return eigenLibrarySolver<Scalar>().solve(a, wantVectors);
}

/// Restores the process's warning handler; collects what is warned meanwhile.
struct CollectedWarnings {
  std::vector<std::string> seen;
  WarningHandler previous =
      setWarningHandler([this](const std::string& text) { seen.push_back(text); });
  ~CollectedWarnings() { setWarningHandler(previous); }
};

TEST(EigenCheck, SoundAnswersOfBothSolversPassAtBothPrecisions) {
  for (int n : {1, 2, 3, 8, 40, 150}) {
    for (int rows : {n / 2 + 1, 2 * n}) {
      SCOPED_TRACE(testing::Message() << n << "x" << n << " of rank " << std::min(n, rows));
      const auto a = gram<double>(n, rows, n + rows);
      const auto f = gram<float>(n, rows, n + rows);
      for (bool vectors : {false, true}) {
        EXPECT_EQ(eigenAnswerFault(a, lapackSolver<double>().solve(a, vectors), vectors), "");
        EXPECT_EQ(eigenAnswerFault(a, sound(a, vectors), vectors), "");
        EXPECT_EQ(eigenAnswerFault(f, lapackSolver<float>().solve(f, vectors), vectors), "");
        EXPECT_EQ(eigenAnswerFault(f, sound(f, vectors), vectors), "");
      }
    }
  }
  // The zero matrix and one that is not positive: the identities hold for any symmetric A.
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(5, 5);
  EXPECT_EQ(eigenAnswerFault(zero, sound(zero, true), true), "");
  const Eigen::MatrixXd indefinite = gram<double>(6, 12, 3) - 10 * Eigen::MatrixXd::Identity(6, 6);
  EXPECT_EQ(eigenAnswerFault(indefinite, sound(indefinite, true), true), "");
}

TEST(EigenCheck, EachCorruptionIsNamed) {
  const Eigen::MatrixXd a = gram<double>(12, 30, 7);
  const EigenAnswer<double> good = sound(a, true);
  ASSERT_EQ(eigenAnswerFault(a, good, true), "");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto expectFault = [&](const char* what, auto corrupt, const std::string& needle,
                               bool vectors = true) {
    EigenAnswer<double> bad = good;
    corrupt(bad);
    const std::string fault = eigenAnswerFault(a, bad, vectors);
    EXPECT_NE(fault.find(needle), std::string::npos) << what << ": '" << fault << "'";
  };
  expectFault(
      "NaN vector", [&](auto& b) { b.vectors(3, 4) = nan; }, "non-finite eigenvectors");
  expectFault(
      "NaN value", [&](auto& b) { b.ascending[2] = nan; }, "non-finite eigenvalues");
  expectFault(
      "infinite value", [&](auto& b) { b.ascending[0] = -INFINITY; }, "non-finite");
  expectFault(
      "rank beyond the size", [&](auto& b) { b.ascending.conservativeResize(13); },
      "13 eigenvalues for a matrix of size 12");
  expectFault(
      "too few vectors", [&](auto& b) { b.vectors.conservativeResize(12, 11); },
      "eigenvectors of 12x11");
  expectFault(
      "out of order", [&](auto& b) { std::swap(b.ascending[4], b.ascending[9]); }, "out of order");
  expectFault(
      "a value moved", [&](auto& b) { b.ascending[11] *= 1 + 1e-6; }, "sum to");
  // Values whose sum and squares are right, but not the vectors' (a wrong residual).
  expectFault(
      "two vectors swapped", [&](auto& b) { b.vectors.col(5).swap(b.vectors.col(6)); }, "residual");
  expectFault(
      "a vector turned",
      [&](auto& b) {
        const Eigen::VectorXd u = b.vectors.col(2), v = b.vectors.col(3);
        b.vectors.col(2) = 0.8 * u + 0.6 * v, b.vectors.col(3) = -0.6 * u + 0.8 * v;
      },
      "residual");
  expectFault(
      "vectors scaled", [&](auto& b) { b.vectors *= 1 + 1e-9; }, "orthonormal");
  expectFault(
      "LAPACK's own report", [&](auto& b) { b.failure = "dsyevd returned info 2"; }, "info 2",
      false);
  // Values only: the identities still see a wrong value.
  expectFault(
      "values only", [&](auto& b) { b.ascending[3] += 1e-3; }, "sum to", false);
}

/// A solver that answers wrong: LAPACK's answer with NaN in its vectors.
template <typename Scalar>
EigenSolver<Scalar> lyingSolver(const char* name) {
  return {name, [](const SymmetricMatrix<Scalar>& a, bool wantVectors) {
            EigenAnswer<Scalar> answer = lapackSolver<Scalar>().solve(a, wantVectors);
            if (wantVectors) answer.vectors(0, 0) = std::numeric_limits<Scalar>::quiet_NaN();
            answer.ascending[0] = std::numeric_limits<Scalar>::quiet_NaN();
            return answer;
          }};
}

TEST(EigenCheck, AWrongAnswerIsSolvedAgainByEigenWithOneWarning) {
  CollectedWarnings warnings;
  for (int n : {3, 30}) {
    const Eigen::MatrixXf a = gram<float>(n, 2 * n, 11);
    const EigenAnswer<float> answer = checkedEigenAnswer<float>(
        a, true, lyingSolver<float>("a liar"), eigenLibrarySolver<float>());
    EXPECT_EQ(eigenAnswerFault(a, answer, true), "");
    EXPECT_EQ(answer.ascending, sound(a, true).ascending);
  }
  // Once a process (ctest runs each test in one of its own), naming what was
  // wrong and what to set.
  ASSERT_EQ(warnings.seen.size(), 1u);
  EXPECT_NE(warnings.seen[0].find("a liar"), std::string::npos) << warnings.seen[0];
  EXPECT_NE(warnings.seen[0].find("OPENBLAS_CORETYPE=" + cpuBlasCore()), std::string::npos)
      << warnings.seen[0];
}

TEST(EigenCheck, TwoWrongAnswersEndInAClearErrorNotACrash) {
  const Eigen::MatrixXd a = gram<double>(3, 5, 2);
  try {
    checkedEigenAnswer<double>(a, true, lyingSolver<double>("LAPACK's dsyevd (a test's liar)"),
                               lyingSolver<double>("Eigen's solver (a test's liar)"));
    FAIL() << "no error";
  } catch (const UserError& e) {
    const std::string message = e.what();
    for (const char* needle : {"3x3 double matrix", "is wrong twice", "non-finite eigenvalues",
                               "a test's liar", "OPENBLAS_CORETYPE=" /* the value to try */})
      EXPECT_NE(message.find(needle), std::string::npos) << needle << " in: " << message;
    EXPECT_NE(message.find("OPENBLAS_CORETYPE=" + cpuBlasCore()), std::string::npos) << message;
  }
  // Without a retry, the first wrong answer is the error.
  EXPECT_THROW(checkedEigenAnswer<double>(a, false, lyingSolver<double>("a liar"), {}), UserError);
}

TEST(BlasCore, AGenericFallbackOnACpuWithMoreIsReplacedByTheCpusCore) {
  EXPECT_EQ(coreTypeToSet("Prescott", "SkylakeX"), "SkylakeX");
  EXPECT_EQ(coreTypeToSet("Prescott", "Haswell"), "Haswell");
  EXPECT_EQ(coreTypeToSet("Prescott", "Prescott"), "");    // a CPU as old as its kernels
  EXPECT_EQ(coreTypeToSet("Cooperlake", "SkylakeX"), "");  // OpenBLAS knew the CPU
  EXPECT_EQ(coreTypeToSet("Zen", "Haswell"), "");
  // Debian links OpenBLAS; a forced core is the one it runs (ctest runs this
  // suite with OPENBLAS_CORETYPE=PRESCOTT too).
  const char* forced = std::getenv("OPENBLAS_CORETYPE");
  if (forced && std::string(forced) == "PRESCOTT") {
    EXPECT_EQ(blasCore(), "Prescott");
    EXPECT_EQ(blasCoreChosenBy(), "OPENBLAS_CORETYPE");
    EXPECT_EQ(blasCoreUnsuited(), cpuBlasCore() != "Prescott");
  } else if (!forced) {
    EXPECT_EQ(blasCoreChosenBy(), "OpenBLAS");
  }
}

TEST(SymmetricEigen, UnsuitedKernelsAreNotAskedAndTheAnswerIsEigens) {
  // Under OPENBLAS_CORETYPE=PRESCOTT on a CPU with AVX2 every solve is
  // Eigen's; elsewhere LAPACK's. Either way the answer is checked and sound.
  const Eigen::MatrixXd a = gram<double>(20, 9, 4);
  const SymmetricEigen e = symmetricEigen(a, true);
  const EigenAnswer<double> expected =
      (blasCoreUnsuited() ? eigenLibrarySolver<double>() : lapackSolver<double>()).solve(a, true);
  EXPECT_EQ(e.values, expected.ascending.reverse().cwiseMax(0.0));
}

TEST(SymmetricEigen, ManySolvesInParallelWithTheSolveAloneBesideThemAreExact) {
  // TBB workers decompose small matrices while another thread changes
  // OpenBLAS's thread count for its solves alone: every answer equals the same
  // solve made with nothing else running, bit for bit.
  constexpr int kMatrices = 64;
  std::vector<Eigen::MatrixXd> small(kMatrices);
  std::vector<SymmetricEigen> expected(kMatrices);
  for (int i = 0; i < kMatrices; ++i) {
    small[i] = gram<double>(8 + i % 40, 50, 100 + i);
    expected[i] = symmetricEigen(small[i], i % 2 == 0);
  }
  const Eigen::MatrixXd large = gram<double>(300, 300, 9);
  const SymmetricEigen largeExpected = symmetricEigenAlone(large, true);
  std::atomic<bool> done{false};
  std::atomic<int> aloneRuns{0}, aloneMismatches{0};
  std::thread alone([&] {
    while (!done) {
      const SymmetricEigen again = symmetricEigenAlone(large, true);
      aloneMismatches += again.values != largeExpected.values;
      ++aloneRuns;
    }
  });
  std::atomic<int> mismatches{0};
  for (int round = 0; round < 8; ++round)
    tbb::parallel_for(0, kMatrices, [&](int i) {
      const SymmetricEigen e = symmetricEigen(small[i], i % 2 == 0);
      mismatches += e.values != expected[i].values || e.vectors != expected[i].vectors;
    });
  done = true;
  alone.join();
  EXPECT_EQ(mismatches, 0);
  EXPECT_GE(aloneRuns, 1);
  EXPECT_EQ(aloneMismatches, 0);
}

}  // namespace
}  // namespace acpca
