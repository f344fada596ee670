#pragma once
// A model laid out for the relighter's SIMD loops (docs/architecture.md,
// "Relighting a model"): the global basis over the directions some pixel
// sees, each cluster's bases and coefficients k-major in chunks of 16 lanes,
// and the chunks in shading order: by span (kSpanRows consecutive transport
// rows, one task's output) of their first row, then cluster. Built once from a
// Model, read-only afterwards, so relighters with their own per-frame scratch
// can share one.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/huge_pages.h"
#include "model/model.h"
#include "model/model_cluster_reader.h"

namespace acpca {

/// Transport rows per span of the shading order: 96 KB of RGB output, so a
/// thread's writes stay in its L2 cache; enough spans to share between threads.
inline constexpr long long kSpanRows = 8192;

/// What a chunk's 16 lanes hold: 16 rows in a row (their outputs one run of
/// 48 floats) and/or 16 pixels in a row (one run of the image).
inline constexpr std::uint8_t kRowsConsecutive = 1, kPixelsConsecutive = 2;

/// Where a PackedModel takes a model's large arrays from: a Model in memory,
/// or a model file read cluster by cluster (ModelClusterReader).
struct ModelValuesSource {
  int globalBases = 0;
  /// V_g(j, k) = globalBasis[j * rowStride + k * columnStride].
  const float* globalBasis = nullptr;
  long long rowStride = 0, columnStride = 0;
  /// Cluster c's bases, rank rows of N floats (each cluster once, before its
  /// coefficients; any thread).
  std::function<const float*(int c, ClusterScratch& scratch)> bases;
  /// Rows [first, first + rows) of cluster c's coefficients, row-major, in the
  /// model's precision (any thread).
  std::function<const void*(int c, long long first, long long rows, ClusterScratch& scratch)>
      coefficients;
};

struct PackedModel {
  /// Repacks the model's bases and coefficients; the model may be released afterwards.
  explicit PackedModel(const Model& model);
  /// The same from `layout` (a Model's all but its global basis, bases and
  /// coefficients) and the arrays of `source`.
  PackedModel(const Model& layout, const ModelValuesSource& source);

  struct Chunk {
    int cluster;
    long long coefficientOffset;  ///< element index of the chunk's k-major block
  };

  long long rows() const { return geometry.rows(); }
  int clusters() const { return static_cast<int>(ranks.size()); }
  long long spans() const { return static_cast<long long>(spanChunks.size()) - 1; }
  /// The cluster of every row, in the transport's row order (Model::clusterOfRow).
  std::vector<int> clusterOfRow() const;

  TransportHeader geometry;
  std::string method;
  CoeffPrecision precision;
  CoeffPrecision basisPrecision;
  int globalBases = 0;
  bool hasMean = false;
  std::vector<int> ranks;
  std::vector<float> scale;  ///< per cluster basis: the i8 step, else 1

  std::vector<int> seenTexels;  ///< row elements (texel, or channel x texel) V_g sees
  /// With R, G and B rows: where each channel's elements start in seenTexels.
  std::array<int, 4> partStart{};
  HugePageVector<float> globalBasis;  ///< N columns of |seen| values (V_g^T, row by row)

  /// W_i^T in basis chunks of 16 bases: per chunk N x 16 values, global index major.
  HugePageVector<float> bases;
  HugePageVector<std::uint16_t> basesF16;  ///< the same in half, for f16-basis models
  std::vector<long long> basisOffset;      ///< per cluster
  std::vector<float> means;                ///< C x N when the model has means
  std::vector<long long> lightingOffset;   ///< per cluster: its first basis among all clusters'
  long long totalRank = 0;                 ///< sum of the ranks

  std::vector<Chunk> chunks;                   ///< in shading order
  std::vector<long long> spanChunks;           ///< per span, its first chunk (+ end)
  HugePageVector<std::int32_t> chunkRows;      ///< 16 per chunk, -1 for padding
  HugePageVector<std::int32_t> chunkPixels;    ///< the same rows' pixel indices
  HugePageVector<float> chunkCoverage;         ///< 16 per chunk: the rows' coverage
  std::vector<std::uint8_t> chunkConsecutive;  ///< per chunk: kRowsConsecutive | kPixelsConsecutive
  HugePageVector<float> chunkAlbedo;           ///< 48 per chunk: R x16, G x16, B x16
  HugePageVector<float> coeffF32;
  HugePageVector<std::uint16_t> coeffF16;
  HugePageVector<std::int8_t> coeffI8;

 private:
  void packGlobalBasis(const Model& m, const ModelValuesSource& source);
  void packClusterBases(const Model& m, const ModelValuesSource& source);
  /// Orders the chunks; returns, per chunk in cluster order (cluster by
  /// cluster, 16 rows each), its place in the shading order.
  std::vector<long long> orderChunks(const Model& m);
  void markConsecutiveChunks();
  void packAlbedo(const Model& m);
  void packCoefficients(const Model& m, const ModelValuesSource& source,
                        const std::vector<long long>& shadingIndexOf);
};

/// A model file packed for relighting, its large arrays read cluster by
/// cluster straight into the packed layout (no copy of the model is kept);
/// every value checked as readModel checks it.
std::shared_ptr<const PackedModel> readPackedModel(const std::string& path);

}  // namespace acpca
