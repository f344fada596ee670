#pragma once
// Eigen-decomposition of symmetric positive semi-definite matrices (Gram and
// covariance matrices), through LAPACK's divide-and-conquer dsyevd.
#include <Eigen/Core>

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
/// any --threads or rank count on a machine. Never call it from parallel work.
SymmetricEigen symmetricEigenAlone(const Eigen::MatrixXd& a, bool wantVectors);

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

}  // namespace acpca
