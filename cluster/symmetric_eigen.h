#pragma once
// Eigen-decomposition of symmetric positive semi-definite matrices (Gram and
// covariance matrices), through LAPACK's divide-and-conquer dsyevd. Every
// answer is checked before use (eigen_check.h); one that fails is solved again
// by Eigen's own solver, and one that fails again ends the command with a
// UserError naming the matrix, what failed and the OPENBLAS_CORETYPE to try.
// Where OpenBLAS runs its generic kernels on a CPU they do not suit
// (blasCoreUnsuited), LAPACK is not asked: Eigen's solver answers, checked.
#include <Eigen/Core>
#include <functional>
#include <string>

#include "cluster/eigen_check.h"

namespace acpca {

struct SymmetricEigen {
  Eigen::VectorXd values;   ///< descending, clamped at 0 (rounding can make them negative)
  Eigen::MatrixXd vectors;  ///< columns match values; empty when not asked for
};

/// a must be symmetric; only its lower triangle is read. LAPACK runs on one
/// thread (set on first use): the callers parallelise over clusters with TBB,
/// and OpenBLAS's own threads inside TBB's tasks would fight them.
SymmetricEigen symmetricEigen(const Eigen::MatrixXd& a, bool wantVectors);

/// The same for one large solve made while no other work runs (the global
/// basis): LAPACK gets min(4, cores) OpenBLAS threads for this call, then one
/// again (2x faster on two cores at 3,700 square). OpenBLAS's result depends on
/// its thread count, so that count ignores --threads: the basis is the same for
/// any --threads or rank count on a machine. The thread count changes under a
/// lock that every other LAPACK call shares: none is in flight meanwhile.
SymmetricEigen symmetricEigenAlone(const Eigen::MatrixXd& a, bool wantVectors);

/// symmetricEigenAlone's LAPACK solve without its checks or retry, values
/// ascending: the solve as it was before every answer was checked, for `bench
/// eigen` to time the checks against (eval/eigen_benchmark.h). Not for models.
EigenAnswer<double> uncheckedLapackAlone(const Eigen::MatrixXd& a, bool wantVectors);

/// The same in single precision (LAPACK ssyevd): about twice as fast, with
/// eigenvalues good to about 1e-7 of the largest. Vectors in float.
struct SymmetricEigenF {
  Eigen::VectorXd values;   ///< descending, clamped at 0
  Eigen::MatrixXf vectors;  ///< empty when not asked for
};
SymmetricEigenF symmetricEigenFloat(const Eigen::MatrixXf& a, bool wantVectors);

/// Smallest n whose top-n eigenvalues hold `fraction` of `total` energy; with
/// fraction >= 1, every eigenvalue above rounding noise (relative 1e-12).
int rankForEnergy(const Eigen::VectorXd& descendingValues, double total, double fraction);

template <typename Scalar>
using SymmetricMatrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

/// A solver of the lower triangle of a symmetric matrix, unchecked.
template <typename Scalar>
struct EigenSolver {
  std::string name;  ///< in words, for messages: "LAPACK's dsyevd (OpenBLAS core Haswell)"
  std::function<EigenAnswer<Scalar>(const SymmetricMatrix<Scalar>&, bool wantVectors)> solve;
};

/// LAPACK's divide and conquer at Scalar's precision, on the calling thread.
template <typename Scalar>
const EigenSolver<Scalar>& lapackSolver();

/// Eigen's SelfAdjointEigenSolver (tridiagonalisation, implicit QL) in double:
/// slower than LAPACK's on large matrices, but no BLAS kernels of its own.
template <typename Scalar>
const EigenSolver<Scalar>& eigenLibrarySolver();

/// `first`'s answer when it passes eigenAnswerFault, else `retry`'s when it
/// does (with a warning, once a process), else a UserError naming the size,
/// each fault, the BLAS core and the OPENBLAS_CORETYPE to try. A retry without
/// a solve function is not made.
template <typename Scalar>
EigenAnswer<Scalar> checkedEigenAnswer(const SymmetricMatrix<Scalar>& a, bool wantVectors,
                                       const EigenSolver<Scalar>& first,
                                       const EigenSolver<Scalar>& retry);

}  // namespace acpca
