#include "cluster/pca.h"

#include <Eigen/Eigenvalues>

#include "precompute/transport/error.h"

namespace acpca {

PcaResult pcaToTolerance(const Eigen::MatrixXd& input, double tolerance, bool subtractMean) {
  ACPCA_CHECK(tolerance >= 0 && tolerance <= 1, "tolerance ", tolerance);
  PcaResult result;
  const Eigen::Index p = input.rows(), n = input.cols();
  result.mean = subtractMean && p > 0 ? Eigen::RowVectorXd(input.colwise().mean())
                                      : Eigen::RowVectorXd::Zero(n);
  const Eigen::MatrixXd rows = input.rowwise() - result.mean;
  result.totalEnergy = rows.squaredNorm();
  result.basis.resize(n, 0);
  if (p == 0 || n == 0 || result.totalEnergy == 0) {
    result.eigenvalues = Eigen::VectorXd::Zero(std::min(p, n));
    return result;
  }
  // Eigen-decompose the smaller Gram matrix; bases then follow from the rows.
  const bool viaRows = p < n;
  const Eigen::MatrixXd gram =
      viaRows ? Eigen::MatrixXd(rows * rows.transpose()) : Eigen::MatrixXd(rows.transpose() * rows);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram);
  ACPCA_CHECK(solver.info() == Eigen::Success, "eigensolver failed on a ", gram.rows(), "^2 Gram");
  const Eigen::Index m = gram.rows();
  result.eigenvalues = solver.eigenvalues().reverse().cwiseMax(0.0);  // clamp rounding below 0
  const Eigen::MatrixXd vectors = solver.eigenvectors().rowwise().reverse();
  // Eigenvalues below this are rounding noise of the Gram product, never kept.
  const double noise = 1e-13 * result.eigenvalues[0];
  const double keep = tolerance * result.totalEnergy;
  double kept = 0;
  int rank = 0;
  while (rank < m && result.eigenvalues[rank] > noise && (tolerance >= 1 || kept < keep))
    kept += result.eigenvalues[rank++];
  result.rank = rank;
  result.residualEnergy = std::max(0.0, result.eigenvalues.tail(m - rank).sum());
  if (viaRows) {  // v_k = rows^T u_k / sigma_k
    result.basis = rows.transpose() * vectors.leftCols(rank);
    for (int k = 0; k < rank; ++k) result.basis.col(k) /= std::sqrt(result.eigenvalues[k]);
  } else {
    result.basis = vectors.leftCols(rank);
  }
  return result;
}

}  // namespace acpca
