#pragma once
// PCA of a set of rows to an energy tolerance: the building block of every
// compression method (docs/design.md section 5). Double precision throughout.
#include <Eigen/Core>

namespace acpca {

using RowMatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct PcaResult {
  Eigen::MatrixXd basis;        ///< cols x n orthonormal principal directions (empty if not asked)
  Eigen::VectorXd eigenvalues;  ///< all of them, descending (squared singular values)
  Eigen::RowVectorXd mean;      ///< subtracted first when asked, else zero
  int rank = 0;                 ///< n: bases kept
  double totalEnergy = 0;       ///< squared norm of the (centred) rows
  double residualEnergy = 0;    ///< what the n bases miss: sum of the dropped eigenvalues
};

/// Keeps the fewest bases whose energy reaches `tolerance` of the total (1 keeps
/// every direction above rounding noise). Decomposes the smaller Gram matrix
/// (rows x rows or cols x cols). All-zero input gives rank 0. With wantBasis
/// false only the eigenvalues (and so rank and residual) are computed, which is
/// much cheaper: the subdivision decisions need nothing more.
PcaResult pcaToTolerance(const Eigen::MatrixXd& rows, double tolerance, bool subtractMean,
                         bool wantBasis = true);

/// Rows centred in double and handed back in float, for the float PCA paths.
struct CentredRowsF {
  RowMatrixF rows;
  Eigen::RowVectorXd mean;  ///< what was subtracted (zero when not asked)
  double energy = 0;        ///< squared norm of the centred rows, summed in double
};
CentredRowsF centreInDouble(const RowMatrixF& rows, bool subtractMean);

/// The smaller of x x^T and x^T x (their non-zero eigenvalues agree), by a
/// symmetric rank-k update: half the multiply-adds of a general product.
Eigen::MatrixXf smallerGram(const RowMatrixF& x);

/// The rank pcaToTolerance would find, from float rows at about three times
/// the speed: the mean and the energy are summed in double, the smaller Gram
/// matrix of the centred rows is formed and decomposed in float (LAPACK's
/// values-only solver, whose BLAS-2 half streams the matrix: float halves its
/// bytes). The eigenvalues are good to about 1e-6 of the largest, which moves
/// the kept fraction far less than 1 - tolerance below 0.9999; tighter
/// tolerances take the double path.
int rankToTolerance(const RowMatrixF& rows, double tolerance, bool subtractMean);

}  // namespace acpca
