#pragma once
// Checks of a symmetric eigen-decomposition before anything uses it: a BLAS
// that picked the wrong kernels for the CPU answers wrong without saying so
// (docs/reliability.md, "When a library answers wrong").
#include <Eigen/Core>
#include <string>

namespace acpca {

/// Each bound is this many times n * ulp * |A|_F (|A|_F^2 for the sum of the
/// squared values; n * ulp alone for orthonormality), as LAPACK's own tests
/// scale their ratios. Sound answers of LAPACK and Eigen stayed below 3.6 on
/// the 33,000 matrices of every method's compress and build, 3x3 to 3,706^2
/// (docs/reliability.md): the bound leaves 28 times that.
inline constexpr double kEigenCheckThreshold = 100;

/// What a solver returned for the symmetric matrix `a` (lower triangle read):
/// its values as returned, ascending and unclamped, and when asked for, the
/// vectors as columns in the same order.
template <typename Scalar>
struct EigenAnswer {
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> ascending;
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> vectors;
  std::string failure;  ///< what the solver itself reported (LAPACK's info), if anything
};

/// Empty when `answer` is a sound decomposition of `a` at Scalar's precision,
/// else what is wrong in words. Checked: the solver's own report, sizes, finite numbers, ascending
/// order, the sum of the values against the trace and the sum of their
/// squares against |A|_F^2 (both exact identities); with vectors, the residual
/// |A V x - V diag(values) x| and |V^T V x - x| on four fixed random vectors x,
/// which sees a wrong column with certainty in practice at O(n^2) cost where
/// the whole of A V - V diag(values) would cost as much as the solve.
template <typename Scalar>
std::string eigenAnswerFault(const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& a,
                             const EigenAnswer<Scalar>& answer, bool wantVectors);

}  // namespace acpca
