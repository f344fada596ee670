#pragma once
// PCA of a set of rows to an energy tolerance: the building block of every
// compression method (design.md section 5). Eigen, double precision.
#include <Eigen/Core>

namespace acpca {

struct PcaResult {
  Eigen::MatrixXd basis;        ///< columns: orthonormal principal directions (cols x n)
  Eigen::VectorXd eigenvalues;  ///< all of them, descending (squared singular values)
  Eigen::RowVectorXd mean;      ///< subtracted first when asked, else zero
  int rank = 0;                 ///< n: bases kept
  double totalEnergy = 0;       ///< sum of squares of the (centred) rows
  double residualEnergy = 0;    ///< what the kept bases miss: sum of dropped eigenvalues
};

/// Keeps the fewest bases whose energy reaches `tolerance` of the total (1 keeps
/// every non-zero direction). Uses the smaller of the row and column Gram
/// matrices. All-zero input gives rank 0.
PcaResult pcaToTolerance(const Eigen::MatrixXd& rows, double tolerance, bool subtractMean);

}  // namespace acpca
