#include "relight/packed_model.h"

#include <tbb/enumerable_thread_specific.h>
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
/// rows, padding lanes zero: a cluster's coefficients, or its bases.
template <typename T>
void packChunks(const T* rowMajor, long long rows, int rank, T* chunks) {
  const long long padded = (rows + kChunkRows - 1) / kChunkRows * kChunkRows;
  for (long long first = 0; first < padded; first += kChunkRows)
    for (int k = 0; k < rank; ++k)
      for (int lane = 0; lane < kChunkRows; ++lane) {
        const long long r = first + lane;
        chunks[first * rank + k * kChunkRows + lane] = r < rows ? rowMajor[r * rank + k] : T(0);
      }
}

long long chunksOf(long long rows) {
  return (rows + kChunkRows - 1) / kChunkRows;
}

/// A model's own arrays as a ModelValuesSource.
ModelValuesSource valuesOf(const Model& m) {
  ModelValuesSource s;
  s.globalBases = m.globalBases();
  s.globalBasis = m.globalBasis.data();  // column-major
  s.rowStride = 1;
  s.columnStride = m.globalBasis.rows();
  s.bases = [&m](int c, ClusterScratch&) { return m.bases.data() + m.basisOffsets[c]; };
  s.coefficients = [&m](int c, long long first, long long, ClusterScratch&) {
    const long long at = m.coefficientOffsets[c] + first * m.ranks[c];
    switch (m.precision) {
      case CoeffPrecision::F32:
        return static_cast<const void*>(m.coeffF32.data() + at);
      case CoeffPrecision::F16:
        return static_cast<const void*>(m.coeffF16.data() + at);
      default:
        return static_cast<const void*>(m.coeffI8.data() + at);
    }
  };
  return s;
}

/// What one thread keeps from cluster to cluster while packing.
struct PackScratch {
  ClusterScratch read;
  std::vector<float> packed;
};

}  // namespace

PackedModel::PackedModel(const Model& m) : PackedModel(m, valuesOf(m)) {}

PackedModel::PackedModel(const Model& m, const ModelValuesSource& source)
    : geometry(m.geometry),
      method(m.method),
      precision(m.precision),
      basisPrecision(m.basisPrecision),
      globalBases(source.globalBases),
      hasMean(m.hasMean),
      ranks(m.ranks),
      scale(m.coeffScale) {
  if (precision != CoeffPrecision::I8) std::fill(scale.begin(), scale.end(), 1.0f);
  if (hasMean) means = m.means;
  packGlobalBasis(m, source);
  packClusterBases(m, source);
  const std::vector<long long> shadingIndexOf = orderChunks(m);
  markConsecutiveChunks();
  packAlbedo(m);
  packCoefficients(m, source, shadingIndexOf);
}

void PackedModel::packGlobalBasis(const Model& m, const ModelValuesSource& source) {
  const int n = globalBases;
  const long long l = m.geometry.rowLength();
  const float* v = source.globalBasis;
  const long long rowStride = source.rowStride, columnStride = source.columnStride;
  // Directions no pixel sees have zero rows in V_g: leave them out. Walk V_g
  // in the order it is stored, not across 4 KB strides.
  std::vector<float> rowMax(static_cast<size_t>(l), 0.0f);
  if (columnStride == 1) {
    tbb::parallel_for(0LL, l, [&](long long j) {
      for (int k = 0; k < n; ++k) rowMax[j] = std::max(rowMax[j], std::abs(v[j * rowStride + k]));
    });
  } else {
    for (int k = 0; k < n; ++k)
      for (long long j = 0; j < l; ++j)
        rowMax[j] = std::max(rowMax[j], std::abs(v[j * rowStride + k * columnStride]));
  }
  for (long long j = 0; j < l; ++j)
    if (n > 0 && rowMax[j] > 0) seenTexels.push_back(static_cast<int>(j));
  const long long seen = static_cast<long long>(seenTexels.size());
  for (int c = 0; c <= 3; ++c)
    partStart[c] = static_cast<int>(std::lower_bound(seenTexels.begin(), seenTexels.end(),
                                                     c * (l / std::max(1, m.geometry.channels))) -
                                    seenTexels.begin());
  globalBasis.resize(seen * n);  // every value set below
  // Blocks of seen rows on all cores: each block's rows stay in cache while
  // the columns are written.
  constexpr long long kBlock = 64;
  tbb::parallel_for(0LL, (seen + kBlock - 1) / kBlock, [&](long long b) {
    const long long first = b * kBlock, last = std::min(seen, first + kBlock);
    for (int k = 0; k < n; ++k)
      for (long long i = first; i < last; ++i)
        globalBasis[k * seen + i] = v[seenTexels[i] * rowStride + k * columnStride];
  });
}

void PackedModel::packClusterBases(const Model& m, const ModelValuesSource& source) {
  // W_i^T in basis chunks of 16 bases, global index by global index: the
  // product W_i^T L_g is then the chunk loop of the shading with 16 bases as
  // lanes. W_i (column-major N x n_i) read as n_i rows of N values packs like
  // a cluster's coefficients, 16 bases to a chunk.
  const int n = globalBases;
  // One allocation, sized first, filled (padding included) by the clusters
  // in parallel, each on the pages it writes.
  long long total = 0;
  for (int c = 0; c < m.clusters(); ++c) {
    basisOffset.push_back(total);
    total += chunksOf(m.ranks[c]) * kChunkRows * static_cast<long long>(n);
  }
  const bool half = basisPrecision == CoeffPrecision::F16;
  (half ? basesF16.resize(total) : bases.resize(total));
  tbb::enumerable_thread_specific<PackScratch> scratch;
  tbb::parallel_for(0, m.clusters(), 1, [&](int c) {
    PackScratch& s = scratch.local();
    const float* values = source.bases(c, s.read);
    const long long count = chunksOf(m.ranks[c]) * kChunkRows * static_cast<long long>(n);
    if (!half) return packChunks(values, m.ranks[c], n, bases.data() + basisOffset[c]);
    s.packed.resize(count);
    packChunks(values, m.ranks[c], n, s.packed.data());
    floatToHalf(s.packed.data(), basesF16.data() + basisOffset[c], count);  // exact: half values
  });
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
  std::vector<long long> shadingIndexOf(order.size());
  long long offset = 0;
  for (size_t j : order) {
    const int c = clusterOf[j];
    const long long first = firstRowPosition[j];
    shadingIndexOf[j] = static_cast<long long>(chunks.size());
    chunks.push_back({c, offset});
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
  return shadingIndexOf;
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

void PackedModel::packCoefficients(const Model& m, const ModelValuesSource& source,
                                   const std::vector<long long>& shadingIndexOf) {
  // Runs of up to kRunChunks chunks of a cluster read at once and each chunk
  // packed straight into its place in the shading order (padding lanes zero):
  // a cluster of many rows still spreads over every core.
  constexpr long long kRunChunks = 256;
  struct Run {
    int cluster;
    long long firstChunk, chunks;  ///< the cluster's chunks, counted from its first
    long long clusterOrderChunk;   ///< the cluster-order index of the run's first chunk
  };
  std::vector<Run> runs;
  long long clusterOrder = 0;
  for (int c = 0; c < m.clusters(); ++c) {
    const long long clusterChunks = chunksOf(m.rowOffsets[c + 1] - m.rowOffsets[c]);
    for (long long first = 0; first < clusterChunks; first += kRunChunks)
      runs.push_back({c, first, std::min(kRunChunks, clusterChunks - first), clusterOrder + first});
    clusterOrder += clusterChunks;
  }
  const size_t total = chunks.empty()
                           ? 0
                           : static_cast<size_t>(chunks.back().coefficientOffset +
                                                 ranks[chunks.back().cluster] * kChunkRows);
  tbb::enumerable_thread_specific<PackScratch> scratch;
  const auto inShadingOrder = [&](auto& packed) {
    using T = typename std::decay_t<decltype(packed)>::value_type;
    packed.resize(total);  // every value set below
    tbb::parallel_for(size_t(0), runs.size(), size_t(1), [&](size_t k) {
      const Run& run = runs[k];
      const int c = run.cluster, rank = ranks[c];
      const long long clusterRows = m.rowOffsets[c + 1] - m.rowOffsets[c];
      const long long first = run.firstChunk * kChunkRows;
      const long long count = std::min(run.chunks * kChunkRows, clusterRows - first);
      const T* values =
          static_cast<const T*>(source.coefficients(c, first, count, scratch.local().read));
      for (long long t = 0; t < run.chunks; ++t) {
        const Chunk& chunk = chunks[shadingIndexOf[run.clusterOrderChunk + t]];
        packChunks(values + t * kChunkRows * rank,
                   std::min<long long>(kChunkRows, count - t * kChunkRows), rank,
                   packed.data() + chunk.coefficientOffset);
      }
    });
  };
  switch (precision) {
    case CoeffPrecision::F32:
      inShadingOrder(coeffF32);
      break;
    case CoeffPrecision::F16:
      inShadingOrder(coeffF16);
      break;
    case CoeffPrecision::I8:
      inShadingOrder(coeffI8);
      break;
  }
}

std::vector<int> PackedModel::clusterOfRow() const {
  std::vector<int> cluster(static_cast<size_t>(rows()), -1);
  for (size_t i = 0; i < chunks.size(); ++i)
    for (int lane = 0; lane < kChunkRows; ++lane)
      if (const int row = chunkRows[i * kChunkRows + lane]; row >= 0)
        cluster[row] = chunks[i].cluster;
  return cluster;
}

std::shared_ptr<const PackedModel> readPackedModel(const std::string& path) {
  const ModelClusterReader reader(path);
  ModelValuesSource source;
  source.globalBases = reader.globalBases();
  source.globalBasis = reader.globalBasisRows();
  source.rowStride = reader.globalBases();
  source.columnStride = 1;
  source.bases = [&](int c, ClusterScratch& s) { return reader.readBases(c, s); };
  source.coefficients = [&](int c, long long first, long long rows, ClusterScratch& s) {
    return reader.readCoefficients(c, first, rows, s);
  };
  auto packed = std::make_shared<const PackedModel>(reader.layout(), source);
  reader.checkRelitBound();
  return packed;
}

}  // namespace acpca
