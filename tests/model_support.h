#pragma once
// The model suites' shared check, two models holding the same clusters and
// values array by array (a round trip, a model written in pieces, a resumed
// build), and a model of many shapes for the relighter's layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/half.h"
#include "model/model.h"

namespace acpca::test {

inline void expectSameModelArrays(const Model& back, const Model& expected) {
  EXPECT_EQ(back.method, expected.method);
  EXPECT_EQ(back.precision, expected.precision);
  EXPECT_TRUE(back.globalBasis == expected.globalBasis);
  EXPECT_EQ(back.ranks, expected.ranks);
  EXPECT_EQ(back.clusterRows, expected.clusterRows);
  EXPECT_EQ(back.rowOffsets, expected.rowOffsets);
  EXPECT_EQ(back.basisOffsets, expected.basisOffsets);
  EXPECT_EQ(back.coefficientOffsets, expected.coefficientOffsets);
  EXPECT_EQ(back.bases, expected.bases);
  EXPECT_EQ(back.means, expected.means);
  EXPECT_EQ(back.coeffF32, expected.coeffF32);
  EXPECT_EQ(back.coeffF16, expected.coeffF16);
  EXPECT_EQ(back.coeffI8, expected.coeffI8);
  EXPECT_EQ(back.coeffScale, expected.coeffScale);
  EXPECT_DOUBLE_EQ(back.transportError, expected.transportError);
  EXPECT_EQ(back.geometry.pixels, expected.geometry.pixels);
  EXPECT_EQ(back.geometry.albedo, expected.geometry.albedo);
}

/// Appends one cluster's coefficients (rows x rank, row-major) in the model's
/// precision (i8 in steps of 1/40), with their per-basis scales and offset.
inline void appendCoefficients(Model& m, const std::vector<float>& u, int rank) {
  const long long count = static_cast<long long>(u.size());
  if (m.precision == CoeffPrecision::F32) m.coeffF32.insert(m.coeffF32.end(), u.begin(), u.end());
  if (m.precision == CoeffPrecision::F16) {
    std::vector<std::uint16_t> h(count);
    floatToHalf(u.data(), h.data(), count);
    m.coeffF16.insert(m.coeffF16.end(), h.begin(), h.end());
  }
  if (m.precision == CoeffPrecision::I8)
    for (float v : u)
      m.coeffI8.push_back(static_cast<std::int8_t>(std::clamp(v * 40.0f, -127.0f, 127.0f)));
  m.coeffScale.insert(m.coeffScale.end(), rank, m.precision == CoeffPrecision::I8 ? 0.025f : 1.0f);
  m.coefficientOffsets.push_back(m.coefficientOffsets.back() + count);
}

/// A model over more rows than several shading bands, whose chunks come in
/// every kind: 16 rows in a row (cluster 0 holds rows 0..9000 in order), rows
/// scattered over the image (the others), rows in a row whose pixels are not
/// (a background pixel every 50), and clusters padded to 16.
inline Model bandedModel(CoeffPrecision precision, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> gauss;
  Model m;
  auto& g = m.geometry;
  const std::vector<int> sizes{9001, 7000, 4003, 16, 1, 1500};
  const std::vector<int> ranks{3, 5, 2, 4, 0, 7};
  long long rows = 0;
  for (int s : sizes) rows += s;
  g.camera.size = {250, 100};
  g.cubemapResolution = 2;
  for (long long r = 0; r < rows; ++r) {
    g.pixels.push_back(static_cast<int>(r + r / 50));
    g.coverage.push_back(0.5f + 0.5f * static_cast<float>(r % 7) / 6);
    for (int c = 0; c < 3; ++c) g.albedo.push_back(0.3f + 0.1f * c);
  }
  const int n = 9;
  m.globalBasis = Eigen::MatrixXf::NullaryExpr(24, n, [&] { return gauss(rng); });
  m.hasMean = true;
  m.precision = precision;
  // Rows 9001.. go to the other clusters in a scattered order (sorted within each).
  const long long rest = rows - sizes[0];
  std::vector<std::int32_t> scattered(rest);
  for (long long i = 0; i < rest; ++i)
    scattered[i] = static_cast<std::int32_t>(sizes[0] + (i * 7919) % rest);
  m.rowOffsets = {0};
  m.basisOffsets = {0};
  m.coefficientOffsets = {0};
  for (size_t c = 0; c < sizes.size(); ++c) {
    const long long begin = m.rowOffsets.back();
    std::vector<std::int32_t> members;
    for (long long i = begin; i < begin + sizes[c]; ++i)
      members.push_back(c == 0 ? static_cast<std::int32_t>(i) : scattered[i - sizes[0]]);
    std::sort(members.begin(), members.end());
    m.clusterRows.insert(m.clusterRows.end(), members.begin(), members.end());
    m.rowOffsets.push_back(begin + sizes[c]);
    m.ranks.push_back(ranks[c]);
    for (int i = 0; i < n * ranks[c]; ++i) m.bases.push_back(gauss(rng));
    m.basisOffsets.push_back(m.bases.size());
    for (int i = 0; i < n; ++i) m.means.push_back(gauss(rng));
    std::vector<float> u(static_cast<size_t>(sizes[c]) * ranks[c]);
    for (auto& v : u) v = gauss(rng);
    appendCoefficients(m, u, ranks[c]);
  }
  return m;
}

}  // namespace acpca::test
