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

CentredRowsF centreInDouble(const RowMatrixF& input, bool subtractMean) {
  CentredRowsF c;
  const Eigen::Index p = input.rows();
  c.mean = Eigen::RowVectorXd::Zero(input.cols());
  if (subtractMean && p > 0) {
    for (Eigen::Index i = 0; i < p; ++i) c.mean += input.row(i).cast<double>();
    c.mean /= static_cast<double>(p);
  }
  // Row by row: no double copy of the whole matrix.
  c.rows.resize(p, input.cols());
  for (Eigen::Index i = 0; i < p; ++i) {
    c.rows.row(i) = (input.row(i).cast<double>() - c.mean).cast<float>();
    c.energy += c.rows.row(i).cast<double>().squaredNorm();
  }
  return c;
}

Eigen::MatrixXf smallerGram(const RowMatrixF& x) {
  const bool viaRows = x.rows() < x.cols();
  const Eigen::Index n = viaRows ? x.rows() : x.cols();
  Eigen::MatrixXf gram = Eigen::MatrixXf::Zero(n, n);
  if (viaRows)
    gram.selfadjointView<Eigen::Lower>().rankUpdate(x);
  else
    gram.selfadjointView<Eigen::Lower>().rankUpdate(x.transpose());
  gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
  return gram;
}

int rankToTolerance(const RowMatrixF& input, double tolerance, bool subtractMean) {
  if (tolerance > 0.9999)
    return pcaToTolerance(input.cast<double>(), tolerance, subtractMean, false).rank;
  if (input.rows() == 0 || input.cols() == 0) return 0;
  const CentredRowsF centred = centreInDouble(input, subtractMean);
  if (centred.energy == 0) return 0;
  const SymmetricEigenF eig = symmetricEigenFloat(smallerGram(centred.rows), false);
  return rankForEnergy(eig.values, centred.energy, tolerance);
}

}  // namespace acpca
