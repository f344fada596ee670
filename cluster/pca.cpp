#include "cluster/pca.h"

#include "cluster/symmetric_eigen.h"
#include "core/error.h"

namespace acpca {

PcaResult pcaToTolerance(const Eigen::MatrixXd& input, double tolerance, bool subtractMean,
                         bool wantBasis) {
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
  // The non-zero eigenvalues of rows rows^T and rows^T rows agree: use the smaller.
  const bool viaRows = p < n;
  Eigen::MatrixXd gram;
  if (viaRows)
    gram.noalias() = rows * rows.transpose();
  else
    gram.noalias() = rows.transpose() * rows;
  const SymmetricEigen eig = symmetricEigen(gram, wantBasis);
  result.eigenvalues = eig.values;
  result.rank = rankForEnergy(eig.values, result.totalEnergy, tolerance);
  result.residualEnergy = std::max(0.0, result.totalEnergy - eig.values.head(result.rank).sum());
  if (!wantBasis) return result;
  if (viaRows) {  // v_k = rows^T u_k / sigma_k
    result.basis = rows.transpose() * eig.vectors.leftCols(result.rank);
    for (int k = 0; k < result.rank; ++k) result.basis.col(k).normalize();
  } else {
    result.basis = eig.vectors.leftCols(result.rank);
  }
  return result;
}

int rankToTolerance(const Eigen::MatrixXf& input, double tolerance, bool subtractMean) {
  if (tolerance > 0.9999)
    return pcaToTolerance(input.cast<double>(), tolerance, subtractMean, false).rank;
  const Eigen::Index p = input.rows();
  if (p == 0 || input.cols() == 0) return 0;
  const Eigen::RowVectorXd mean = subtractMean
                                      ? Eigen::RowVectorXd(input.cast<double>().colwise().mean())
                                      : Eigen::RowVectorXd::Zero(input.cols());
  const Eigen::MatrixXf rows = (input.cast<double>().rowwise() - mean).cast<float>();
  const double total = rows.cast<double>().squaredNorm();
  if (total == 0) return 0;
  Eigen::MatrixXf gram;
  if (p < input.cols())
    gram.noalias() = rows * rows.transpose();
  else
    gram.noalias() = rows.transpose() * rows;
  const SymmetricEigen eig = symmetricEigen(gram.cast<double>(), false);
  return rankForEnergy(eig.values, total, tolerance);
}

}  // namespace acpca
