#include "cluster/model_fit.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "cluster/pca.h"
#include "cluster/quantization.h"
#include "cluster/rank_allocation.h"
#include "cluster/symmetric_eigen.h"
#include "core/error.h"

namespace acpca {

namespace {

/// A fitted cluster. Its basis is kept in float, as the model stores it (not
/// in pca.basis, left empty): with a thousand clusters of rank ~170 over
/// N ~ 2000 the bases in double alone were 3.8 GB at 1024x1024.
struct ClusterFit {
  PcaResult pca;
  Eigen::MatrixXf basis;         // N x n
  Eigen::MatrixXf coefficients;  // p x n
};

/// PCA of a cluster too large to copy in double (global PCA at 1024x1024 has
/// 716k rows of N ~ 2000): the N x N Gram matrix is summed over a fixed split
/// of the rows (so the sum does not depend on the thread count), each block
/// widened to double, and the coefficients are computed block by block.
ClusterFit fitLargeCluster(const RowMatrixF& g, const std::vector<int>& rows, double tolerance,
                           bool subtractMean) {
  const int n = static_cast<int>(g.cols());
  const long long p = static_cast<long long>(rows.size());
  constexpr int kParts = 8;
  constexpr long long kBlock = 2048;
  std::vector<Eigen::MatrixXd> grams(kParts, Eigen::MatrixXd::Zero(n, n));
  std::vector<Eigen::RowVectorXd> sums(kParts, Eigen::RowVectorXd::Zero(n));
  tbb::parallel_for(0, kParts, [&](int part) {
    const long long first = p * part / kParts, last = p * (part + 1) / kParts;
    Eigen::MatrixXd block;
    for (long long b = first; b < last; b += kBlock) {
      const long long count = std::min(kBlock, last - b);
      block.resize(count, n);
      for (long long i = 0; i < count; ++i) block.row(i) = g.row(rows[b + i]).cast<double>();
      grams[part].selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
      sums[part] += block.colwise().sum();
    }
  });
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(n);
  for (int part = 0; part < kParts; ++part) gram += grams[part], sum += sums[part];
  gram = gram.selfadjointView<Eigen::Lower>();
  ClusterFit fit;
  PcaResult& pca = fit.pca;
  pca.mean = subtractMean ? Eigen::RowVectorXd(sum / double(p)) : Eigen::RowVectorXd::Zero(n);
  gram -= double(p) * pca.mean.transpose() * pca.mean;  // centre: sum (g - mu)(g - mu)^T
  pca.totalEnergy = std::max(0.0, gram.trace());
  const SymmetricEigen eig = symmetricEigen(gram, true);
  pca.eigenvalues = eig.values;
  pca.rank = pca.totalEnergy > 0 ? rankForEnergy(eig.values, pca.totalEnergy, tolerance) : 0;
  pca.residualEnergy = std::max(0.0, pca.totalEnergy - eig.values.head(pca.rank).sum());
  fit.basis = eig.vectors.leftCols(pca.rank).cast<float>();
  const Eigen::MatrixXf& basis = fit.basis;
  const Eigen::RowVectorXf mean = pca.mean.cast<float>();
  fit.coefficients.resize(p, pca.rank);
  tbb::parallel_for(0LL, (p + kBlock - 1) / kBlock, [&](long long b) {
    const long long first = b * kBlock, count = std::min(kBlock, p - first);
    Eigen::MatrixXf block(count, n);
    for (long long i = 0; i < count; ++i) block.row(i) = g.row(rows[first + i]) - mean;
    fit.coefficients.middleRows(first, count).noalias() = block * basis;
  });
  return fit;
}

/// PCA of one cluster in float: the smaller Gram matrix of the rows centred in
/// double, decomposed by LAPACK in single precision, the coefficients projected
/// in float. Twice as fast as double and half the memory; the residual comes
/// from the coefficients themselves, |g - mu|^2 - |u|^2 summed in double, so it
/// is exact for the basis kept whatever the eigensolver's rounding. Used where
/// the tolerance leaves room for float (<= 0.9999); tighter fits stay double.
ClusterFit fitClusterFloat(const RowMatrixF& g, const std::vector<int>& rows, double tolerance,
                           bool subtractMean) {
  const int n = static_cast<int>(g.cols());
  const long long p = static_cast<long long>(rows.size());
  RowMatrixF gathered(p, n);
  for (long long i = 0; i < p; ++i) gathered.row(i) = g.row(rows[i]);
  const CentredRowsF centred = centreInDouble(gathered, subtractMean);
  const RowMatrixF& x = centred.rows;
  ClusterFit fit;
  PcaResult& pca = fit.pca;
  pca.mean = centred.mean;
  pca.totalEnergy = centred.energy;
  fit.basis.resize(n, 0);
  fit.coefficients.resize(p, 0);
  if (p == 0 || pca.totalEnergy == 0) {
    pca.eigenvalues = Eigen::VectorXd::Zero(std::min<long long>(p, n));
    return fit;
  }
  const bool viaRows = p < n;
  const Eigen::MatrixXf gram = smallerGram(x);
  const SymmetricEigenF eig = symmetricEigenFloat(gram, true);
  pca.eigenvalues = eig.values;
  pca.rank = rankForEnergy(eig.values, pca.totalEnergy, tolerance);
  Eigen::MatrixXf& basis = fit.basis;
  if (viaRows) {  // v_k = x^T u_k / sigma_k
    basis = x.transpose() * eig.vectors.leftCols(pca.rank);
    for (int k = 0; k < pca.rank; ++k) basis.col(k).normalize();
  } else {
    basis = eig.vectors.leftCols(pca.rank);
  }
  fit.coefficients = x * basis;
  pca.residualEnergy =
      std::max(0.0, pca.totalEnergy - fit.coefficients.cast<double>().squaredNorm());
  return fit;
}

/// sum over rows of |g_p - mu_c - W_c u_p|^2 with the stored (quantized)
/// values: the cluster part of the transport error, exact for any precision.
double reconstructionError(const Model& m, const RowMatrixF& g) {
  const int n = m.globalBases();
  std::vector<double> perCluster(m.clusters(), 0.0);
  tbb::parallel_for(0, m.clusters(), [&](int c) {
    const long long p = m.rowOffsets[c + 1] - m.rowOffsets[c];
    const int rank = m.ranks[c];
    const Eigen::Map<const Eigen::MatrixXf> w(m.bases.data() + m.basisOffsets[c], n, rank);
    const Eigen::Map<const Eigen::RowVectorXf> mean(m.means.data() + static_cast<size_t>(c) * n, n);
    constexpr long long kBlock = 1024;
    Eigen::MatrixXf rows, u;
    for (long long first = 0; first < p; first += kBlock) {
      const long long count = std::min(kBlock, p - first);
      rows.resize(count, n);
      u.resize(count, rank);
      for (long long i = 0; i < count; ++i) {
        rows.row(i) = g.row(m.clusterRows[m.rowOffsets[c] + first + i]) - mean;
        for (int k = 0; k < rank; ++k) u(i, k) = m.coefficient(c, first + i, k);
      }
      rows.noalias() -= u * w.transpose();
      perCluster[c] += rows.cast<double>().squaredNorm();
    }
  });
  double sum = 0;
  for (double e : perCluster) sum += e;  // fixed order
  return sum;
}

}  // namespace

Model buildModel(const TransportHeader& geometry, const GlobalBasis& basis,
                 const GlobalProjection& projection, const Partition& partition,
                 const ModelOptions& options) {
  const int n = basis.globalBases();
  Model m;
  m.geometry = geometry;
  m.globalBasis = basis.basis;
  m.hasMean = options.mean;
  ACPCA_CHECK(options.basisPrecision != CoeffPrecision::I8, "bases are f32 or f16");
  m.basisPrecision = options.basisPrecision;
  const int clusters = static_cast<int>(partition.size());

  std::vector<ClusterFit> fits(clusters);
  const double tolerance = options.allocateRanks ? 1.0 : options.tolerance;
  const auto large = [&](int c) {
    return static_cast<long long>(partition[c].size()) * n > options.largeClusterValues;
  };
  for (int c = 0; c < clusters; ++c)  // one at a time: each is parallel inside
    if (large(c))
      fits[c] = fitLargeCluster(projection.coefficients, partition[c], tolerance, options.mean);
  const bool inFloat = options.floatFits && tolerance <= 0.9999;
  tbb::parallel_for(0, clusters, [&](int c) {
    if (large(c)) return;
    if (inFloat) {
      fits[c] = fitClusterFloat(projection.coefficients, partition[c], tolerance, options.mean);
      return;
    }
    Eigen::MatrixXd rows(partition[c].size(), n);
    for (size_t i = 0; i < partition[c].size(); ++i)
      rows.row(i) = projection.coefficients.row(partition[c][i]).cast<double>();
    fits[c].pca = pcaToTolerance(rows, tolerance, options.mean, true);
    fits[c].coefficients = ((rows.rowwise() - fits[c].pca.mean) * fits[c].pca.basis).cast<float>();
    fits[c].basis = fits[c].pca.basis.cast<float>();
    fits[c].pca.basis.resize(0, 0);
  });
  if (options.allocateRanks) {
    std::vector<Eigen::VectorXd> spectra;
    std::vector<long long> sizes;
    double energy = 0;
    for (const auto& f : fits) {
      spectra.push_back(f.pca.eigenvalues);
      sizes.push_back(f.coefficients.rows());
      energy += f.pca.totalEnergy;
    }
    const std::vector<int> ranks =
        allocateRanks(spectra, sizes, n, (1 - options.tolerance) * energy);
    for (int c = 0; c < clusters; ++c) {  // keep the leading ranks[c] bases
      ClusterFit& f = fits[c];
      const int r = std::min(ranks[c], f.pca.rank);
      f.pca.residualEnergy = std::max(0.0, f.pca.totalEnergy - f.pca.eigenvalues.head(r).sum());
      f.pca.rank = r;
      f.basis = f.basis.leftCols(r).eval();
      f.coefficients = f.coefficients.leftCols(r).eval();
    }
  }

  m.rowOffsets.push_back(0);
  m.basisOffsets.push_back(0);
  m.coefficientOffsets.push_back(0);
  m.means.assign(static_cast<size_t>(clusters) * n, 0.0f);
  size_t basisValues = 0, coefficientValues = 0;  // reserved: no doubling while appending
  for (const ClusterFit& f : fits) {
    basisValues += static_cast<size_t>(f.basis.size());
    coefficientValues += static_cast<size_t>(f.coefficients.size());
  }
  m.bases.reserve(basisValues);
  m.coeffF32.reserve(coefficientValues);
  double clusterResidual = 0, quantizationError = 0;
  for (int c = 0; c < clusters; ++c) {
    ClusterFit& f = fits[c];
    const int rank = f.pca.rank;
    m.clusterRows.insert(m.clusterRows.end(), partition[c].begin(), partition[c].end());
    m.rowOffsets.push_back(m.clusterRows.size());
    m.ranks.push_back(rank);
    m.bases.insert(m.bases.end(), f.basis.data(), f.basis.data() + f.basis.size());
    m.basisOffsets.push_back(m.bases.size());
    for (int k = 0; k < n; ++k) m.means[static_cast<size_t>(c) * n + k] = float(f.pca.mean[k]);
    clusterResidual += f.pca.residualEnergy;
    // Row-major p x n coefficients, stored as asked once all are in.
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> u = f.coefficients;
    const size_t count = u.size();
    m.coeffF32.insert(m.coeffF32.end(), u.data(), u.data() + count);
    m.coefficientOffsets.push_back(m.coefficientOffsets.back() + static_cast<long long>(count));
    f = ClusterFit();  // release as we go: one cluster may hold most of the model
  }
  m.precision = CoeffPrecision::F32;
  quantizationError = storeCoefficients(m, options.precision);
  if (m.basisPrecision == CoeffPrecision::F16) {
    roundToHalf(m.bases);
    roundToHalf(m.means);
    clusterResidual = reconstructionError(m, projection.coefficients);
    quantizationError = 0;  // included
  }
  const double total = projection.transportEnergy();
  const double globalResidual = projection.residualEnergy.sum();
  m.globalEnergyKept = total > 0 ? 1 - globalResidual / total : 1;
  m.transportError =
      total > 0
          ? std::sqrt(std::max(0.0, globalResidual + clusterResidual + quantizationError) / total)
          : 0;
  return m;
}

}  // namespace acpca
