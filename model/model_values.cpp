#include "model/model_values.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/half.h"

namespace acpca {

namespace {

/// sum_i |values_i| in double, over independent partial sums (one chain of
/// additions would wait on each one's latency).
double absSum(const float* values, long long count) {
  double part[8] = {};
  long long i = 0;
  for (; i + 8 <= count; i += 8)
    for (int p = 0; p < 8; ++p) part[p] += std::abs(double(values[i + p]));
  for (; i < count; ++i) part[0] += std::abs(double(values[i]));
  return ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7]));
}

/// sum_k |u_k| weight_k in double, likewise.
template <typename T>
double weightedAbsSum(const T* u, const double* weight, int rank) {
  double part[4] = {};
  int k = 0;
  for (; k + 4 <= rank; k += 4)
    for (int p = 0; p < 4; ++p) part[p] += std::abs(double(u[k + p])) * weight[k + p];
  for (; k < rank; ++k) part[0] += std::abs(double(u[k])) * weight[k];
  return (part[0] + part[1]) + (part[2] + part[3]);
}

}  // namespace

ClusterBoundTerms clusterBoundTerms(const ClusterValues& v) {
  const int rank = v.rank, n = v.globalBases;
  ClusterBoundTerms t;
  t.weight.assign(rank, 0.0);
  for (int k = 0; k < rank; ++k) {
    t.weight[k] = absSum(v.bases + static_cast<long long>(k) * n, n);
    if (v.precision == CoeffPrecision::I8) t.weight[k] *= std::abs(v.scale[k]);
  }
  t.mean = absSum(v.mean, n);
  return t;
}

double rowsBound(const ClusterValues& v, const ClusterBoundTerms& t) {
  const int rank = v.rank;
  double worst = 0;
  bool finite = true;
  std::vector<float> decoded(v.precision == CoeffPrecision::F16 ? rank : 0);
  for (long long r = 0; r < v.rows; ++r) {
    const long long at = r * rank;
    double row = t.mean;
    switch (v.precision) {
      case CoeffPrecision::F32:
        row +=
            weightedAbsSum(static_cast<const float*>(v.coefficients) + at, t.weight.data(), rank);
        break;
      case CoeffPrecision::F16:
        halfToFloat(static_cast<const std::uint16_t*>(v.coefficients) + at, decoded.data(), rank);
        row += weightedAbsSum(decoded.data(), t.weight.data(), rank);
        break;
      case CoeffPrecision::I8:
        row += weightedAbsSum(static_cast<const std::int8_t*>(v.coefficients) + at, t.weight.data(),
                              rank);
        break;
    }
    finite = finite && row <= std::numeric_limits<double>::max();
    worst = std::max(worst, row);
  }
  return finite ? worst : std::numeric_limits<double>::infinity();
}

double globalBasisBound(const Eigen::MatrixXf& globalBasis) {
  double projection = 0;
  for (long long j = 0; j < globalBasis.cols(); ++j)
    projection = std::max(projection, double(globalBasis.col(j).cwiseAbs().sum()));
  return projection;
}

double largestAlbedo(const TransportHeader& geometry) {
  double albedo = 0;
  for (float a : geometry.albedo) albedo = std::max(albedo, double(a));
  return albedo;
}

double relitBoundPerUnitLight(const Model& m) {
  // Clusters in parallel; a maximum does not depend on the order.
  const double worstRow = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, m.clusters()), 0.0,
      [&](const tbb::blocked_range<int>& range, double worst) {
        for (int c = range.begin(); c != range.end(); ++c) {
          const ClusterValues v = m.clusterValues(c);
          worst = std::max(worst, rowsBound(v, clusterBoundTerms(v)));
        }
        return worst;
      },
      [](double a, double b) { return std::max(a, b); });
  return largestAlbedo(m.geometry) * worstRow * globalBasisBound(m.globalBasis);
}

namespace {

template <typename T>
void requireFinite(const T* values, long long count, const char* what, const std::string& ctx) {
  for (long long i = 0; i < count; ++i)
    if (!std::isfinite(static_cast<float>(values[i])))
      throw UserError(concat(ctx, ": non-finite ", what));
}

}  // namespace

void checkBasesFinite(const ClusterValues& v, const std::string& ctx) {
  const long long n = v.globalBases;
  requireFinite(v.bases, v.rank * n, "basis value", ctx);
  requireFinite(v.mean, n, "cluster mean", ctx);
  requireFinite(v.scale, v.rank, "coefficient scale", ctx);
}

void checkCoefficientsFinite(const ClusterValues& v, const std::string& ctx) {
  const long long coefficients = v.rows * v.rank;
  if (v.precision == CoeffPrecision::F32)
    requireFinite(static_cast<const float*>(v.coefficients), coefficients, "coefficient", ctx);
  if (v.precision == CoeffPrecision::F16) {
    // A half is finite unless its exponent bits are all ones.
    const auto* h = static_cast<const std::uint16_t*>(v.coefficients);
    for (long long i = 0; i < coefficients; ++i)
      if ((h[i] & 0x7c00) == 0x7c00) throw UserError(concat(ctx, ": non-finite coefficient"));
  }
}

void checkRelitBound(double bound, const std::string& ctx) {
  // Orthonormal bases and transport values below 1 keep real models many orders
  // below this; 1e20 still leaves lighting up to ~1e18 per
  // lattice direction before a relit value could overflow a float.
  if (!(bound <= kRelitBoundLimit))
    throw UserError(concat(ctx, ": values out of range (relit values could overflow)"));
}

void checkModelValues(const Model& m, const std::string& ctx) {
  for (int c = 0; c < m.clusters(); ++c) {
    checkBasesFinite(m.clusterValues(c), ctx);
    checkCoefficientsFinite(m.clusterValues(c), ctx);
  }
  requireFinite(m.globalBasis.data(), m.globalBasis.size(), "global basis value", ctx);
  checkRelitBound(relitBoundPerUnitLight(m), ctx);
}

}  // namespace acpca
