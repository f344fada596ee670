#include "eval/sh_transport.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>

#include "core/error.h"
#include "core/half.h"
#include "eval/error_measures.h"
#include "transport/row_stream.h"

namespace acpca {

ShTransport::ShTransport(const TransportReader& transport, int maxCoefficients,
                         int normalResolution)
    : rows_(transport.rows()),
      maxCoefficients_(maxCoefficients),
      latticeSize_(transport.latticeSize()),
      channels_(transport.header().channels),
      albedo_(transport.header().albedo) {
  const int bands = shBandsOf(maxCoefficients, "SH coefficients");
  if (normalResolution < 1 || normalResolution > 64)
    throw UserError(
        concat("SH normal groups: cube resolution ", normalResolution, " is outside 1..64"));
  const TransportHeader& header = transport.header();
  // The columns: the lattice's texels, or a captured light set's lights
  // (the basis fits over the light directions, weighted by their cells).
  const ColumnGeometry columns = columnGeometry(header);
  const CubeLattice coarse(normalResolution);
  sh_ = shAtDirections(columns.directions, bands);
  shTransposed_ = sh_.transpose().cast<float>();

  // Groups: rows by the coarse texel their normal falls in, numbered in texel order.
  std::vector<int> texelOfRow(rows_);
  std::vector<Vec3> normal(rows_);
  for (long long p = 0; p < rows_; ++p) {
    // Captured images have no normals: their rows are one group.
    Vec3 n = header.normals.empty() ? Vec3::UnitZ()
                                    : Vec3(header.normals[3 * p], header.normals[3 * p + 1],
                                           header.normals[3 * p + 2]);
    if (!(n.norm() > 0) || !n.allFinite()) n = Vec3::UnitZ();  // support comes from its texels
    normal[p] = n.normalized();
    texelOfRow[p] = coarse.texelOf(normal[p]);
  }
  std::map<int, int> groupOfTexel;
  for (int t : texelOfRow) groupOfTexel.emplace(t, 0);
  std::vector<Vec3> groupNormal;
  for (auto& [texel, g] : groupOfTexel) {
    g = static_cast<int>(groupNormal.size());
    groupNormal.push_back(coarse.direction(texel));
  }
  const int groupCount = static_cast<int>(groupNormal.size());
  groupOfRow_.resize(rows_);
  std::vector<double> lowestCosine(groupCount, 1);  // of the widest member normal
  for (long long p = 0; p < rows_; ++p) {
    const int g = groupOfRow_[p] = groupOfTexel[texelOfRow[p]];
    lowestCosine[g] = std::min(lowestCosine[g], normal[p].dot(groupNormal[g]));
  }

  // One pass over T: b = Y^T W f and the energy of every row, and the texels
  // each group's rows light.
  Eigen::MatrixXd weightedSh = sh_;
  for (int j = 0; j < latticeSize_; ++j) weightedSh.row(j) *= columns.solidAngles[j];
  // With R, G and B rows each channel's row is fitted on its own: fit row
  // p channels + c (the row-major [count, channels l] block read as
  // [count channels, l]).
  const long long fitRows = rows_ * channels_;
  projections_.resize(fitRows, maxCoefficients_);
  energies_.assign(fitRows, 0);
  std::vector<std::vector<unsigned char>> lit(groupCount,
                                              std::vector<unsigned char>(latticeSize_, 0));
  streamRowBlocks(
      transport, rowsPerBlock(transport), [&](long long first, long long count, const float* rows) {
        const Eigen::Map<
            const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
            block(rows, count * channels_, latticeSize_);
        projections_.middleRows(first * channels_, count * channels_).noalias() =
            block.cast<double>() * weightedSh;
        for (long long r = 0; r < count * channels_; ++r) {
          std::vector<unsigned char>& mask = lit[groupOfRow_[(first * channels_ + r) / channels_]];
          double energy = 0;
          for (int j = 0; j < latticeSize_; ++j) {
            const double f = block(r, j);
            if (f == 0) continue;
            energy += columns.solidAngles[j] * f * f;
            std::atomic_ref<unsigned char> flag(mask[j]);
            if (!flag.load(std::memory_order_relaxed)) flag.store(1, std::memory_order_relaxed);
          }
          energies_[first * channels_ + r] = energy;
        }
      });

  // Supports and Gram matrices A = Y_S^T W_S Y_S ([Lam06] eq. 7-8).
  supports_.resize(groupCount);
  grams_.resize(groupCount);
  tbb::parallel_for(0, groupCount, [&](int g) {
    const double horizon = -std::sqrt(std::max(0.0, 1 - lowestCosine[g] * lowestCosine[g]));
    for (int j = 0; j < latticeSize_; ++j)
      if (lit[g][j] || columns.directions[j].dot(groupNormal[g]) >= horizon)
        supports_[g].push_back(j);
    Eigen::MatrixXd rootWeighted(supports_[g].size(), maxCoefficients_);
    for (size_t k = 0; k < supports_[g].size(); ++k) {
      const int j = supports_[g][k];
      rootWeighted.row(k) = sh_.row(j) * std::sqrt(columns.solidAngles[j]);
    }
    grams_[g] = rootWeighted.transpose() * rootWeighted;
  });
  fits_.resize(bands + 1);
}

const ShSupportFit& ShTransport::factored(int g, int n) const {
  return *fits_[shBandsOf(n, "SH coefficients")][g];
}

ShCoefficients ShTransport::fit(int n, ShFit fit) const {
  const int bands = shBandsOf(n, "SH coefficients");
  if (n > maxCoefficients_)
    throw UserError(concat("SH coefficients: ", n, " is more than the ", maxCoefficients_,
                           " this baseline was built for"));
  auto& fits = fits_[bands];
  if (fits.empty()) {
    fits.resize(groups());
    tbb::parallel_for(0, groups(), [&](int g) {
      fits[g] = std::make_unique<ShSupportFit>(grams_[g].topLeftCorner(n, n));
    });
  }
  ShCoefficients c;
  c.n = n;
  c.fit = fit;
  const long long fitRows = rows_ * channels_;
  c.values.resize(static_cast<size_t>(fitRows) * n);
  c.norms.resize(fitRows);
  c.bounds.resize(fitRows);
  tbb::parallel_for(0LL, fitRows, [&](long long p) {
    const ShSupportFit& f = *fits[groupOfRow_[p / channels_]];
    std::vector<double> coefficients(n);
    f.fit(fit, projections_.row(p).data(), energies_[p], coefficients.data());
    double norm = 0;
    for (int i = 0; i < n; ++i) {
      c.values[p * n + i] = static_cast<float>(coefficients[i]);
      norm += coefficients[i] * coefficients[i];
    }
    c.norms[p] = static_cast<float>(std::sqrt(norm));
    c.bounds[p] = static_cast<float>(std::sqrt(f.coefficientBound(energies_[p])));
  });
  return c;
}

ShStatistics ShTransport::statistics(const ShCoefficients& c) const {
  ShStatistics s;
  std::vector<double> conditions, norms, ratios;
  for (int g = 0; g < groups(); ++g) conditions.push_back(factored(g, c.n).conditionNumber());
  for (size_t p = 0; p < c.bounds.size(); ++p) {
    if (!(c.bounds[p] > 0)) continue;  // a row with no energy has c = 0
    norms.push_back(c.norms[p]);
    ratios.push_back(c.norms[p] / c.bounds[p]);
  }
  s.medianCondition = median(conditions);
  s.maxCondition = conditions.empty() ? 0 : *std::max_element(conditions.begin(), conditions.end());
  s.medianNorm = median(norms);
  s.maxNorm = norms.empty() ? 0 : *std::max_element(norms.begin(), norms.end());
  s.medianNormToBound = median(ratios);
  s.maxNormToBound = ratios.empty() ? 0 : *std::max_element(ratios.begin(), ratios.end());
  return s;
}

void ShTransport::relight(const ShCoefficients& c, const LatticeLighting& lighting, float* rgb) {
  ACPCA_CHECK(static_cast<long long>(lighting.size()) == 3LL * latticeSize_, "lighting has ",
              lighting.size(), " values for a lattice of ", latticeSize_);
  ACPCA_CHECK(static_cast<long long>(c.values.size()) == rows_ * channels_ * c.n, "coefficients ",
              c.values.size(), " for ", rows_, " rows of ", channels_, " x ", c.n);
  const int n = c.n;
  // Per group and channel: the integral of each SH function against the
  // lighting over the support, Y_S^T L_S (eq. 5's dual vector, exact on the lattice).
  lightingOnSupports_.resize(n, 3 * groups());
  tbb::parallel_for(0, groups(), [&](int g) {
    Eigen::Matrix<float, Eigen::Dynamic, 3> sum =
        Eigen::Matrix<float, Eigen::Dynamic, 3>::Zero(n, 3);
    for (int j : supports_[g]) {
      const auto y = shTransposed_.col(j).head(n);
      for (int ch = 0; ch < 3; ++ch) sum.col(ch) += y * static_cast<float>(lighting[3 * j + ch]);
    }
    lightingOnSupports_.middleCols(3 * g, 3) = sum;
  });
  tbb::parallel_for(tbb::blocked_range<long long>(0, rows_, 1024),
                    [&](const tbb::blocked_range<long long>& range) {
                      for (long long p = range.begin(); p < range.end(); ++p) {
                        const auto l = lightingOnSupports_.middleCols(3 * groupOfRow_[p], 3);
                        for (int ch = 0; ch < 3; ++ch) {
                          const long long fitRow = p * channels_ + (channels_ == 3 ? ch : 0);
                          const Eigen::Map<const Eigen::VectorXf> u(c.values.data() + fitRow * n,
                                                                    n);
                          rgb[3 * p + ch] = albedo_[3 * p + ch] * u.dot(l.col(ch));
                        }
                      }
                    });
}

double ShTransport::costPerPixel(int n) const {
  double supportTexels = 0;
  for (const auto& s : supports_) supportTexels += s.size();
  // In RGB triples: with R, G and B rows each channel has its own n coefficients.
  return rows_ ? n + n * supportTexels / rows_ : 0;
}

long long ShTransport::frameBytes(const ShCoefficients& c) const {
  const int bytes = c.storage == CoeffPrecision::F32 ? 4 : c.storage == CoeffPrecision::F16 ? 2 : 1;
  return rows_ * (static_cast<long long>(channels_) * c.n * bytes + 4 + 12);
}

void storeShCoefficients(ShCoefficients& c, CoeffPrecision storage) {
  ACPCA_CHECK(c.storage == CoeffPrecision::F32, "coefficients already stored as ",
              coeffPrecisionName(c.storage));
  c.storage = storage;
  if (storage == CoeffPrecision::F32) return;
  if (storage == CoeffPrecision::F16) {
    // Beyond the half range a value saturates (ULS coefficients can get there).
    for (float& v : c.values) v = std::clamp(v, -kHalfMax, kHalfMax);
    std::vector<std::uint16_t> half(c.values.size());
    floatToHalf(c.values.data(), half.data(), half.size());
    halfToFloat(half.data(), c.values.data(), half.size());
    return;
  }
  const long long rows = c.n ? static_cast<long long>(c.values.size()) / c.n : 0;
  for (int i = 0; i < c.n; ++i) {
    float largest = 0;
    for (long long p = 0; p < rows; ++p)
      largest = std::max(largest, std::abs(c.values[p * c.n + i]));
    const float scale = largest > 0 ? largest / 127.0f : 1.0f;
    for (long long p = 0; p < rows; ++p) {
      float& v = c.values[p * c.n + i];
      v = std::clamp(std::round(v / scale), -127.0f, 127.0f) * scale;
    }
  }
}

}  // namespace acpca
