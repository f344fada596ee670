#include "relight/packed_model.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <type_traits>

#include "core/half.h"
#include "relight/relight_kernels.h"

namespace acpca {

using kernels::kChunkRows;

namespace {

/// Copies `rows` rows of `rank` values (row-major) into k-major chunks of 16
/// rows (padding lanes stay zero): a cluster's coefficients, or its bases.
template <typename T>
void packCluster(const T* rowMajor, long long rows, int rank, T* chunks) {
  for (long long r = 0; r < rows; ++r)
    for (int k = 0; k < rank; ++k)
      chunks[(r / kChunkRows) * rank * kChunkRows + k * kChunkRows + r % kChunkRows] =
          rowMajor[r * rank + k];
}

}  // namespace

PackedModel::PackedModel(const Model& m)
    : geometry(m.geometry),
      precision(m.precision),
      basisPrecision(m.basisPrecision),
      globalBases(m.globalBases()),
      hasMean(m.hasMean),
      ranks(m.ranks),
      scale(m.coeffScale) {
  if (precision != CoeffPrecision::I8) std::fill(scale.begin(), scale.end(), 1.0f);
  if (hasMean) means = m.means;
  packGlobalBasis(m);
  packClusterBases(m);
  const std::vector<long long> firstRowOf = orderChunks(m);
  markConsecutiveChunks();
  packAlbedo(m);
  packCoefficients(m, firstRowOf);
}

void PackedModel::packGlobalBasis(const Model& m) {
  const int n = globalBases;
  const long long l = m.globalBasis.rows();
  // Directions no pixel sees have zero rows in V_g: leave them out. V_g is
  // stored column by column: walk it so, not row by row across 4 KB strides.
  std::vector<float> rowMax(static_cast<size_t>(l), 0.0f);
  for (int k = 0; k < n; ++k)
    for (long long j = 0; j < l; ++j)
      rowMax[j] = std::max(rowMax[j], std::abs(m.globalBasis(j, k)));
  for (long long j = 0; j < l; ++j)
    if (n > 0 && rowMax[j] > 0) seenTexels.push_back(static_cast<int>(j));
  const long long seen = static_cast<long long>(seenTexels.size());
  for (int c = 0; c <= 3; ++c)
    partStart[c] = static_cast<int>(std::lower_bound(seenTexels.begin(), seenTexels.end(),
                                                     c * (l / std::max(1, m.geometry.channels))) -
                                    seenTexels.begin());
  globalBasis.resize(seen * n);
  for (int k = 0; k < n; ++k)
    for (long long i = 0; i < seen; ++i)
      globalBasis[k * seen + i] = m.globalBasis(seenTexels[i], k);
}

void PackedModel::packClusterBases(const Model& m) {
  // W_i^T in basis chunks of 16 bases, global index by global index: the
  // product W_i^T L_g is then the chunk loop of the shading with 16 bases as
  // lanes. W_i (column-major N x n_i) read as n_i rows of N values packs like
  // a cluster's coefficients, 16 bases to a chunk.
  const int n = globalBases;
  // One allocation, sized first, and the clusters packed in parallel: grown
  // cluster by cluster it was copied again at each doubling, onto fresh pages.
  long long total = 0;
  for (int c = 0; c < m.clusters(); ++c) {
    basisOffset.push_back(total);
    total += (m.ranks[c] + kChunkRows - 1) / kChunkRows * kChunkRows * static_cast<long long>(n);
  }
  HugePageVector<float> packed(static_cast<size_t>(total), 0.0f);
  tbb::parallel_for(0, m.clusters(), [&](int c) {
    packCluster(m.bases.data() + m.basisOffsets[c], m.ranks[c], n, packed.data() + basisOffset[c]);
  });
  if (basisPrecision == CoeffPrecision::F16) {
    basesF16.resize(packed.size());
    floatToHalf(packed.data(), basesF16.data(), packed.size());  // exact: half values
  } else {
    bases = std::move(packed);
  }
  lightingOffset.resize(ranks.size());
  totalRank = 0;
  for (size_t c = 0; c < ranks.size(); ++c) {
    lightingOffset[c] = totalRank;
    totalRank += ranks[c];
  }
}

std::vector<long long> PackedModel::orderChunks(const Model& m) {
  // Each cluster's rows in groups of 16, in cluster order first.
  std::vector<int> clusterOf;
  std::vector<long long> firstRowPosition;
  for (int c = 0; c < m.clusters(); ++c)
    for (long long r = m.rowOffsets[c]; r < m.rowOffsets[c + 1]; r += kChunkRows) {
      clusterOf.push_back(c);
      firstRowPosition.push_back(r);
    }
  // Shading order: by span of the first row (rows run in image order), then
  // cluster, as chunks were made.
  const auto spanOf = [&](size_t j) { return m.clusterRows[firstRowPosition[j]] / kSpanRows; };
  std::vector<size_t> order(clusterOf.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return spanOf(a) < spanOf(b); });

  spanChunks.assign(std::max(1LL, (rows() + kSpanRows - 1) / kSpanRows) + 1, 0);
  std::vector<long long> firstRowOf;
  long long offset = 0;
  for (size_t j : order) {
    const int c = clusterOf[j];
    const long long first = firstRowPosition[j];
    chunks.push_back({c, offset});
    firstRowOf.push_back(first);
    offset += ranks[c] * kChunkRows;
    ++spanChunks[spanOf(j) + 1];
    for (int lane = 0; lane < kChunkRows; ++lane) {
      const int row = first + lane < m.rowOffsets[c + 1] ? m.clusterRows[first + lane] : -1;
      chunkRows.push_back(row);
      chunkPixels.push_back(row >= 0 ? m.geometry.pixels[row] : -1);
      chunkCoverage.push_back(row >= 0 ? m.geometry.coverage[row] : 0.0f);
    }
  }
  for (size_t s = 1; s < spanChunks.size(); ++s) spanChunks[s] += spanChunks[s - 1];
  return firstRowOf;
}

void PackedModel::markConsecutiveChunks() {
  chunkConsecutive.assign(chunks.size(), 0);
  for (size_t j = 0; j < chunks.size(); ++j) {
    const std::int32_t* rowsOf = chunkRows.data() + j * kChunkRows;
    const std::int32_t* pixels = chunkPixels.data() + j * kChunkRows;
    bool rowRun = true, pixelRun = true;
    for (int lane = 1; lane < kChunkRows; ++lane) {
      rowRun = rowRun && rowsOf[lane] == rowsOf[0] + lane;
      pixelRun = pixelRun && rowsOf[lane] >= 0 && pixels[lane] == pixels[0] + lane;
    }
    chunkConsecutive[j] = (rowRun ? kRowsConsecutive : 0) | (pixelRun ? kPixelsConsecutive : 0);
  }
}

void PackedModel::packAlbedo(const Model& m) {
  chunkAlbedo.assign(chunks.size() * 3 * kChunkRows, 0.0f);
  for (size_t j = 0; j < chunks.size(); ++j)
    for (int lane = 0; lane < kChunkRows; ++lane)
      if (const int row = chunkRows[j * kChunkRows + lane]; row >= 0)
        for (int c = 0; c < 3; ++c)
          chunkAlbedo[(j * 3 + c) * kChunkRows + lane] = m.geometry.albedo[3 * row + c];
}

void PackedModel::packCoefficients(const Model& m, const std::vector<long long>& firstRowOf) {
  // Each chunk's coefficients straight from the model's row-major ones into
  // their place in the shading order (padding lanes stay zero).
  const size_t total = chunks.empty()
                           ? 0
                           : static_cast<size_t>(chunks.back().coefficientOffset +
                                                 ranks[chunks.back().cluster] * kChunkRows);
  const auto inShadingOrder = [&](const auto& source) {
    using T = typename std::decay_t<decltype(source)>::value_type;
    HugePageVector<T> packed(total);
    tbb::parallel_for(size_t(0), chunks.size(), [&](size_t i) {
      const int c = chunks[i].cluster, rank = ranks[c];
      const long long first = firstRowOf[i];
      const long long count = std::min<long long>(kChunkRows, m.rowOffsets[c + 1] - first);
      packCluster(source.data() + m.coefficientOffsets[c] + (first - m.rowOffsets[c]) * rank, count,
                  rank, packed.data() + chunks[i].coefficientOffset);
    });
    return packed;
  };
  switch (precision) {
    case CoeffPrecision::F32:
      coeffF32 = inShadingOrder(m.coeffF32);
      break;
    case CoeffPrecision::F16:
      coeffF16 = inShadingOrder(m.coeffF16);
      break;
    case CoeffPrecision::I8:
      coeffI8 = inShadingOrder(m.coeffI8);
      break;
  }
}

}  // namespace acpca
