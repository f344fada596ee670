#include "cluster/model_values.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/half.h"

namespace acpca {

double relitBoundPerUnitLight(const Model& m) {
  const long long n = m.globalBases();
  double projection = 0;  // max_j sum_i |V_g(i, j)|: bounds |(V_g^T L)_j| / max|L|
  for (long long j = 0; j < n; ++j)
    projection = std::max(projection, double(m.globalBasis.col(j).cwiseAbs().sum()));
  double worstRow = 0;
  std::vector<double> basisNorm;
  for (int c = 0; c < m.clusters(); ++c) {
    basisNorm.assign(m.ranks[c], 0.0);
    for (int k = 0; k < m.ranks[c]; ++k)
      for (long long j = 0; j < n; ++j)
        basisNorm[k] += std::abs(m.bases[m.basisOffsets[c] + k * n + j]);
    double mean = 0;
    for (long long j = 0; j < n; ++j) mean += std::abs(m.means[c * n + j]);
    for (long long r = 0; r < m.rowOffsets[c + 1] - m.rowOffsets[c]; ++r) {
      double row = mean;
      for (int k = 0; k < m.ranks[c]; ++k) row += std::abs(m.coefficient(c, r, k)) * basisNorm[k];
      worstRow = std::max(worstRow, row);
    }
  }
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
