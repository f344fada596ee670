#include "model/model_values.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/half.h"

namespace acpca {

namespace {

/// max over the cluster's rows of mean + sum_k |u_rk| weight_k, the
/// coefficients read in their stored type (|q| x scale for i8).
double worstRowOfCluster(const Model& m, int c, double mean, const std::vector<double>& weight) {
  const int rank = m.ranks[c];
  const long long rows = m.rowOffsets[c + 1] - m.rowOffsets[c];
  const long long first = m.coefficientOffsets[c];
  double worst = rows > 0 ? mean : 0;
  std::vector<float> decoded(m.precision == CoeffPrecision::F16 ? rank : 0);
  for (long long r = 0; r < rows; ++r) {
    double row = mean;
    const long long at = first + r * rank;
    switch (m.precision) {
      case CoeffPrecision::F32:
        for (int k = 0; k < rank; ++k) row += std::abs(double(m.coeffF32[at + k])) * weight[k];
        break;
      case CoeffPrecision::F16:
        halfToFloat(m.coeffF16.data() + at, decoded.data(), rank);
        for (int k = 0; k < rank; ++k) row += std::abs(double(decoded[k])) * weight[k];
        break;
      case CoeffPrecision::I8:
        for (int k = 0; k < rank; ++k) row += std::abs(int(m.coeffI8[at + k])) * weight[k];
        break;
    }
    worst = std::max(worst, row);
  }
  return worst;
}

}  // namespace

double relitBoundPerUnitLight(const Model& m) {
  const long long n = m.globalBases();
  double projection = 0;  // max_j sum_i |V_g(i, j)|: bounds |(V_g^T L)_j| / max|L|
  for (long long j = 0; j < n; ++j)
    projection = std::max(projection, double(m.globalBasis.col(j).cwiseAbs().sum()));
  // Clusters in parallel; a maximum does not depend on the order.
  const double worstRow = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, m.clusters()), 0.0,
      [&](const tbb::blocked_range<int>& range, double worst) {
        std::vector<double> weight;
        for (int c = range.begin(); c != range.end(); ++c) {
          weight.assign(m.ranks[c], 0.0);
          for (int k = 0; k < m.ranks[c]; ++k) {
            for (long long j = 0; j < n; ++j)
              weight[k] += std::abs(m.bases[m.basisOffsets[c] + k * n + j]);
            if (m.precision == CoeffPrecision::I8)
              weight[k] *= std::abs(m.coeffScale[m.firstBasisIndex(c) + k]);
          }
          double mean = 0;
          for (long long j = 0; j < n; ++j) mean += std::abs(m.means[c * n + j]);
          worst = std::max(worst, worstRowOfCluster(m, c, mean, weight));
        }
        return worst;
      },
      [](double a, double b) { return std::max(a, b); });
  double albedo = 0;
  for (float a : m.geometry.albedo) albedo = std::max(albedo, double(a));
  return albedo * worstRow * projection;
}

void checkModelValues(const Model& m, const std::string& ctx) {
  const auto finite = [&](const auto& values, const char* what) {
    for (float v : values)
      if (!std::isfinite(v)) throw UserError(concat(ctx, ": non-finite ", what));
  };
  finite(m.bases, "basis value");
  finite(m.means, "cluster mean");
  finite(m.coeffF32, "coefficient");
  finite(m.coeffScale, "coefficient scale");
  finite(Eigen::Map<const Eigen::VectorXf>(m.globalBasis.data(), m.globalBasis.size()),
         "global basis value");
  if (m.precision == CoeffPrecision::F16) {
    std::vector<float> decoded(m.coeffF16.size());
    halfToFloat(m.coeffF16.data(), decoded.data(), decoded.size());
    finite(decoded, "coefficient");
  }
  // Orthonormal bases and transport values below 1 keep real models many orders
  // below this; 1e20 still leaves lighting up to ~1e18 per
  // lattice direction before a relit value could overflow a float.
  if (!(relitBoundPerUnitLight(m) <= kRelitBoundLimit))
    throw UserError(concat(ctx, ": values out of range (relit values could overflow)"));
}

}  // namespace acpca
