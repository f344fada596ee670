#include "cluster/eigen_check.h"

#include <cmath>
#include <limits>
#include <random>

#include "core/error.h"

namespace acpca {

namespace {

constexpr int kProbes = 4;

/// Probe vectors, the same for every call of a size: the check is repeatable.
Eigen::MatrixXd probeVectors(Eigen::Index n) {
  std::mt19937_64 rng(0x5eed + static_cast<std::uint64_t>(n));
  std::normal_distribution<double> normal;
  Eigen::MatrixXd x(n, kProbes);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(rng);
  return x;
}

/// The worst probe's |e_j| / |x_j|.
double worstProbeRatio(const Eigen::MatrixXd& errors, const Eigen::MatrixXd& x) {
  double worst = 0;
  for (int j = 0; j < kProbes; ++j) worst = std::max(worst, errors.col(j).norm() / x.col(j).norm());
  return worst;
}

}  // namespace

template <typename Scalar>
std::string eigenAnswerFault(const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& a,
                             const EigenAnswer<Scalar>& answer, bool wantVectors) {
  const Eigen::Index n = a.rows();
  if (!answer.failure.empty()) return answer.failure;
  if (answer.ascending.size() != n)
    return concat(answer.ascending.size(), " eigenvalues for a matrix of size ", n);
  if (wantVectors && (answer.vectors.rows() != n || answer.vectors.cols() != n))
    return concat("eigenvectors of ", answer.vectors.rows(), "x", answer.vectors.cols(),
                  " for a matrix of size ", n);
  if (n == 0) return {};
  if (!answer.ascending.allFinite()) return "non-finite eigenvalues";
  if (wantVectors && !answer.vectors.allFinite()) return "non-finite eigenvectors";
  const Eigen::VectorXd values = answer.ascending.template cast<double>();
  for (Eigen::Index i = 1; i < n; ++i)
    if (values[i] < values[i - 1])
      return concat("eigenvalues out of order (", values[i - 1], " before ", values[i], ")");

  // The lower triangle as the solver read it, summed in double.
  double trace = 0, frobenius2 = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    trace += double(a(j, j));
    frobenius2 += double(a(j, j)) * double(a(j, j));
    for (Eigen::Index i = j + 1; i < n; ++i) frobenius2 += 2 * double(a(i, j)) * double(a(i, j));
  }
  const double norm = std::sqrt(frobenius2);
  const double unit = double(n) * std::numeric_limits<Scalar>::epsilon();
  const double bound = kEigenCheckThreshold * unit;
  // Exact identities of any symmetric matrix: sum = trace, sum of squares = |A|_F^2.
  const double traceRatio = std::abs(values.sum() - trace) / (unit * norm);
  if (!(std::abs(values.sum() - trace) <= bound * norm))
    return concat("the eigenvalues sum to ", values.sum(), " against a trace of ", trace, " (",
                  traceRatio, " n ulp |A|)");
  const double squares = values.squaredNorm();
  if (!(std::abs(squares - frobenius2) <= bound * frobenius2))
    return concat("the squared eigenvalues sum to ", squares, " against |A|_F^2 = ", frobenius2);
  if (!wantVectors || norm == 0) return {};

  // In double: no copy where Scalar is double (the global basis's 3,700^2).
  const Eigen::Ref<const Eigen::MatrixXd> lower(a.template cast<double>());
  const Eigen::Ref<const Eigen::MatrixXd> v(answer.vectors.template cast<double>());
  const Eigen::MatrixXd x = probeVectors(n);
  const Eigen::MatrixXd y = v * x;
  const Eigen::MatrixXd residual =
      lower.template selfadjointView<Eigen::Lower>() * y - v * (values.asDiagonal() * x);
  const double residualRatio = worstProbeRatio(residual, x) / (unit * norm);
  if (!(residualRatio <= kEigenCheckThreshold))
    return concat("the residual |A v - lambda v| is ", residualRatio, " n ulp |A| (bound ",
                  kEigenCheckThreshold, ")");
  const Eigen::MatrixXd drift = v.transpose() * y - x;
  const double orthonormality = worstProbeRatio(drift, x) / unit;
  if (!(orthonormality <= kEigenCheckThreshold))
    return concat("the eigenvectors are not orthonormal: |V^T V x - x| is ", orthonormality,
                  " n ulp |x| (bound ", kEigenCheckThreshold, ")");
  return {};
}

template std::string eigenAnswerFault<double>(const Eigen::MatrixXd&, const EigenAnswer<double>&,
                                              bool);
template std::string eigenAnswerFault<float>(const Eigen::MatrixXf&, const EigenAnswer<float>&,
                                             bool);

}  // namespace acpca
