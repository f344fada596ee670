#include "relight/model_relighter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/error.h"
#include "core/half.h"
#include "relight/relight_kernels.h"

namespace acpca {

using kernels::kChunkRows;

namespace {

/// Rows per band of the shading order: 96 KB of RGB output, so a thread's
/// writes stay in its L2 cache; enough bands to share between threads.
constexpr long long kBandRows = 8192;

/// What the chunk's 16 lanes hold: 16 rows in a row (their outputs one run of
/// 48 floats) and/or 16 pixels in a row (one run of the image).
constexpr std::uint8_t kRowsConsecutive = 1, kPixelsConsecutive = 2;

/// A chunk of 16 consecutive rows: one run the compiler writes in vectors.
void storeRows(const float (*shaded)[kChunkRows], const float* albedo, float* __restrict out) {
  for (int lane = 0; lane < kChunkRows; ++lane)
    for (int ch = 0; ch < 3; ++ch)
      out[3 * lane + ch] = albedo[ch * kChunkRows + lane] * shaded[ch][lane];
}

/// The same into 16 consecutive image pixels of `stride` floats, coverage-weighted.
template <int stride>
void addPixels(const float (*shaded)[kChunkRows], const float* albedo, const float* coverage,
               float* __restrict out) {
  for (int lane = 0; lane < kChunkRows; ++lane)
    for (int ch = 0; ch < 3; ++ch)
      out[stride * lane + ch] +=
          coverage[lane] * (albedo[ch * kChunkRows + lane] * shaded[ch][lane]);
}

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

ModelRelighter::ModelRelighter(const Model& m)
    : geometry_(m.geometry),
      precision_(m.precision),
      globalBases_(m.globalBases()),
      hasMean_(m.hasMean),
      basisPrecision_(m.basisPrecision),
      ranks_(m.ranks),
      scale_(m.coeffScale) {
  const int n = globalBases_;
  const long long l = m.globalBasis.rows();
  // Directions no pixel sees have zero rows in V_g: leave them out.
  for (long long j = 0; j < l; ++j)
    if (n > 0 && m.globalBasis.row(j).cwiseAbs().maxCoeff() > 0)
      seenTexels_.push_back(static_cast<int>(j));
  const long long seen = static_cast<long long>(seenTexels_.size());
  for (int c = 0; c <= 3; ++c)
    partStart_[c] = static_cast<int>(std::lower_bound(seenTexels_.begin(), seenTexels_.end(),
                                                      c * (l / std::max(1, m.geometry.channels))) -
                                     seenTexels_.begin());
  globalBasis_.resize(seen * n);
  for (int k = 0; k < n; ++k)
    for (long long i = 0; i < seen; ++i)
      globalBasis_[k * seen + i] = m.globalBasis(seenTexels_[i], k);
  // W_i^T in tiles of 16 bases, global index by global index: the phase-2
  // product W_i^T L_g is then the chunk loop of phase 3 with 16 bases as lanes.
  // W_i (column-major N x n_i) read as n_i rows of N values packs like a
  // cluster's coefficients, 16 bases to a tile.
  HugePageVector<float> tiles;
  for (int c = 0; c < m.clusters(); ++c) {
    basisOffset_.push_back(static_cast<long long>(tiles.size()));
    const size_t start = tiles.size();
    tiles.resize(
        start + (m.ranks[c] + kChunkRows - 1) / kChunkRows * kChunkRows * static_cast<size_t>(n),
        0.0f);
    packCluster(m.bases.data() + m.basisOffsets[c], m.ranks[c], n, tiles.data() + start);
  }
  if (basisPrecision_ == CoeffPrecision::F16) {
    basesF16_.resize(tiles.size());
    floatToHalf(tiles.data(), basesF16_.data(), tiles.size());  // exact: half values
  } else {
    bases_ = std::move(tiles);
  }
  if (hasMean_) means_ = m.means;
  if (precision_ != CoeffPrecision::I8) std::fill(scale_.begin(), scale_.end(), 1.0f);

  // Chunks: each cluster's rows in groups of 16, coefficients k-major within.
  // Until the shading order is known, a chunk's offset is the position of its
  // first row in the model's cluster-ordered row list.
  const int clusters = m.clusters();
  lightingOffset_.push_back(0);
  for (int c = 0; c < clusters; ++c) {
    const long long p = m.rowOffsets[c + 1] - m.rowOffsets[c];
    const long long chunkCount = (p + kChunkRows - 1) / kChunkRows;
    for (long long j = 0; j < chunkCount; ++j) {
      chunks_.push_back({c, m.rowOffsets[c] + j * kChunkRows});
      for (int lane = 0; lane < kChunkRows; ++lane) {
        const long long r = j * kChunkRows + lane;
        chunkRows_.push_back(r < p ? m.clusterRows[m.rowOffsets[c] + r] : -1);
      }
    }
    lightingOffset_.push_back(lightingOffset_.back() + ranks_[c]);
  }
  const long long totalRank = lightingOffset_.back();
  lightingOffset_.pop_back();

  // Shading order: by band of the first row (rows run in image order), then
  // cluster, as chunks were made. Coefficients are packed in that order.
  const long long bands = std::max(1LL, (rows() + kBandRows - 1) / kBandRows);
  const auto bandOf = [&](size_t j) { return chunkRows_[j * kChunkRows] / kBandRows; };
  std::vector<size_t> order(chunks_.size());
  for (size_t j = 0; j < order.size(); ++j) order[j] = j;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return bandOf(a) < bandOf(b); });
  const std::vector<Chunk> clusterOrder = std::move(chunks_);
  const HugePageVector<std::int32_t> clusterOrderRows = std::move(chunkRows_);
  chunks_.clear(), chunkRows_.clear();
  bandChunks_.assign(bands + 1, 0);
  long long offset = 0;
  for (size_t j : order) {
    const int c = clusterOrder[j].cluster;
    chunks_.push_back({c, offset});
    offset += ranks_[c] * kChunkRows;
    ++bandChunks_[clusterOrderRows[j * kChunkRows] / kBandRows + 1];
    for (int lane = 0; lane < kChunkRows; ++lane) {
      const int row = clusterOrderRows[j * kChunkRows + lane];
      chunkRows_.push_back(row);
      chunkPixels_.push_back(row >= 0 ? m.geometry.pixels[row] : -1);
      chunkCoverage_.push_back(row >= 0 ? m.geometry.coverage[row] : 0.0f);
    }
  }
  for (long long b = 0; b < bands; ++b) bandChunks_[b + 1] += bandChunks_[b];
  chunkConsecutive_.assign(chunks_.size(), 0);
  for (size_t j = 0; j < chunks_.size(); ++j) {
    const std::int32_t* rows = chunkRows_.data() + j * kChunkRows;
    const std::int32_t* pixels = chunkPixels_.data() + j * kChunkRows;
    bool rowRun = true, pixelRun = true;
    for (int lane = 1; lane < kChunkRows; ++lane) {
      rowRun = rowRun && rows[lane] == rows[0] + lane;
      pixelRun = pixelRun && rows[lane] >= 0 && pixels[lane] == pixels[0] + lane;
    }
    chunkConsecutive_[j] = (rowRun ? kRowsConsecutive : 0) | (pixelRun ? kPixelsConsecutive : 0);
  }
  // Each chunk's coefficients straight from the model's row-major ones into
  // their place in the shading order (padding lanes stay zero).
  const auto inShadingOrder = [&](const auto& source) {
    using T = typename std::decay_t<decltype(source)>::value_type;
    HugePageVector<T> packed(static_cast<size_t>(offset));
    tbb::parallel_for(size_t(0), order.size(), [&](size_t i) {
      const int c = chunks_[i].cluster, rank = ranks_[c];
      const long long first = clusterOrder[order[i]].coefficientOffset;  // first row's position
      const long long count = std::min<long long>(kChunkRows, m.rowOffsets[c + 1] - first);
      packCluster(source.data() + m.coefficientOffsets[c] + (first - m.rowOffsets[c]) * rank, count,
                  rank, packed.data() + chunks_[i].coefficientOffset);
    });
    return packed;
  };
  chunkAlbedo_.assign(chunks_.size() * 3 * kChunkRows, 0.0f);
  for (size_t j = 0; j < chunks_.size(); ++j)
    for (int lane = 0; lane < kChunkRows; ++lane)
      if (const int row = chunkRows_[j * kChunkRows + lane]; row >= 0)
        for (int c = 0; c < 3; ++c)
          chunkAlbedo_[(j * 3 + c) * kChunkRows + lane] = m.geometry.albedo[3 * row + c];
  switch (precision_) {
    case CoeffPrecision::F32:
      coeffF32_ = inShadingOrder(m.coeffF32);
      break;
    case CoeffPrecision::F16:
      coeffF16_ = inShadingOrder(m.coeffF16);
      break;
    case CoeffPrecision::I8:
      coeffI8_ = inShadingOrder(m.coeffI8);
      break;
  }

  light_.assign(3 * seen, 0.0f);
  globalLighting_.assign(3 * static_cast<size_t>(n), 0.0f);
  globalLightingRgb_.assign(3 * static_cast<size_t>(n), 0.0f);
  clusterLighting_.assign(3 * totalRank, 0.0f);
  meanTerm_.assign(3 * static_cast<size_t>(clusters), 0.0f);
  activeRanks_ = ranks_;
}

void ModelRelighter::setMaxRank(int k) {
  std::vector<int> active = ranks_;
  if (k >= 0)
    for (int& r : active) r = std::min(r, k);
  activeRanks_ = std::move(active);
}

void ModelRelighter::setRankFraction(double fraction) {
  if (!(fraction >= 0 && fraction <= 1))
    throw UserError(concat("rank fraction ", fraction, " is not in [0, 1]"));
  std::vector<int> active = ranks_;
  for (int& r : active) r = std::min(r, static_cast<int>(std::ceil(fraction * r - 1e-9)));
  activeRanks_ = std::move(active);
}

long long ModelRelighter::bytesPerFrame() const {
  const long long elementBytes = precision_ == CoeffPrecision::F32   ? 4
                                 : precision_ == CoeffPrecision::F16 ? 2
                                                                     : 1;
  const long long basisBytes = basisPrecision_ == CoeffPrecision::F16 ? 2 : 4;
  long long bytes = static_cast<long long>(globalBasis_.size()) * 4;
  for (size_t c = 0; c < activeRanks_.size(); ++c)
    bytes += (activeRanks_[c] + kChunkRows - 1) / kChunkRows * kChunkRows *
                 static_cast<long long>(globalBases_) * basisBytes +
             (hasMean_ ? globalBases_ * 4LL : 0);
  for (const Chunk& chunk : chunks_)
    bytes += activeRanks_[chunk.cluster] * kChunkRows * elementBytes;
  // Row indices and albedo of every chunk.
  bytes += static_cast<long long>(chunks_.size()) * kChunkRows * (4 + 12);
  return bytes;
}

double ModelRelighter::costPerPixel() const {
  // V_g^T L, in multiply-adds of RGB triples: with R, G and B rows each value
  // meets one channel, so three of them make one triple.
  double cost = static_cast<double>(globalBasis_.size()) / geometry_.channels;
  std::vector<long long> rowsOf(activeRanks_.size(), 0);
  for (const Chunk& chunk : chunks_) rowsOf[chunk.cluster] += kChunkRows;
  for (size_t c = 0; c < activeRanks_.size(); ++c)
    cost += (activeRanks_[c] + (hasMean_ ? 1 : 0)) * double(globalBases_) +
            activeRanks_[c] * double(std::min<long long>(rowsOf[c], rows()));
  return rows() ? cost / rows() : 0;
}

void ModelRelighter::lightGlobal(const LatticeLighting& lighting) {
  const long long l = 6LL * geometry_.cubemapResolution * geometry_.cubemapResolution;
  ACPCA_CHECK(static_cast<long long>(lighting.size()) == 3 * l, "lighting has ", lighting.size(),
              " values for a lattice of ", l);
  const int n = globalBases_;
  const int seen = static_cast<int>(seenTexels_.size());
  // With R, G and B rows side by side, channel c's light meets only the c-th
  // third of V_g's rows (row_layout.h).
  const bool rgbRows = geometry_.channels == 3;
  for (int i = 0; i < seen; ++i) {
    const long long j = seenTexels_[i] % l, part = seenTexels_[i] / l;
    for (int c = 0; c < 3; ++c)
      light_[c * seen + i] = !rgbRows || c == part ? static_cast<float>(lighting[3 * j + c]) : 0.0f;
  }
  // L_g = V_g^T L (as n x 3 interleaved, and split by channel), in fixed
  // blocks of 16 columns so each column's summation order never depends on how
  // TBB splits the work.
  const float* light[3] = {light_.data(), light_.data() + seen, light_.data() + 2 * seen};
  constexpr int kBlock = 16;
  tbb::parallel_for(0, (n + kBlock - 1) / kBlock, [&](int block) {
    const int first = block * kBlock, count = std::min(kBlock, n - first);
    float out[3 * kBlock];
    if (rgbRows) {
      // Each channel meets its own third of the column alone: seenTexels_ is
      // sorted, so that third is one run [partStart_[c], partStart_[c + 1]).
      for (int k = 0; k < count; ++k)
        for (int c = 0; c < 3; ++c) {
          const int begin = partStart_[c], length = partStart_[c + 1] - begin;
          using Vec = Eigen::Map<const Eigen::VectorXf>;
          out[3 * k + c] =
              length > 0
                  ? Vec(globalBasis_.data() + static_cast<size_t>(first + k) * seen + begin, length)
                        .dot(Vec(light[c] + begin, length))
                  : 0.0f;
        }
    } else {
      kernels::dotRgbColumns(globalBasis_.data() + static_cast<size_t>(first) * seen, count, light,
                             seen, out);
    }
    for (int k = 0; k < count; ++k)
      for (int c = 0; c < 3; ++c) {
        globalLighting_[c * n + first + k] = out[3 * k + c];
        globalLightingRgb_[3 * (first + k) + c] = out[3 * k + c];
      }
  });
}

/// L_i = W_i^T L_g (the i8 step folded in) and the mean term mu_i . L_g.
template <typename B>
void ModelRelighter::lightCluster(int c, const HugePageVector<B>& bases) {
  const int n = globalBases_;
  float* li = clusterLighting_.data() + 3 * lightingOffset_[c];
  const float zero[3] = {0, 0, 0};
  float tile[3][kChunkRows];
  for (int first = 0; first < activeRanks_[c]; first += kChunkRows) {
    kernels::shadeChunk(bases.data() + basisOffset_[c] + static_cast<size_t>(first) * n,
                        globalLightingRgb_.data(), n, zero, tile);
    for (int k = first; k < std::min(first + kChunkRows, activeRanks_[c]); ++k)
      for (int ch = 0; ch < 3; ++ch)
        li[3 * k + ch] = tile[ch][k - first] * scale_[lightingOffset_[c] + k];
  }
  float* mean = meanTerm_.data() + 3 * c;
  const float* lg[3] = {globalLighting_.data(), globalLighting_.data() + n,
                        globalLighting_.data() + 2 * n};
  if (hasMean_)
    kernels::dotRgb(means_.data() + size_t(c) * n, lg, n, mean);
  else
    mean[0] = mean[1] = mean[2] = 0;
}

/// Every chunk of one band: u_p . L_i times albedo (eq. 17).
template <typename T>
void ModelRelighter::shadeBand(int band, const HugePageVector<T>& coefficients,
                               const Output& out) const {
  // Every output line of the band is written this frame, and none is in cache
  // any more (a frame streams far more than the caches hold): ask for them all
  // for writing now, in order, instead of one cache miss per chunk later.
  const long long firstRow = band * kBandRows, lastRow = std::min(rows(), firstRow + kBandRows) - 1;
  if (lastRow >= firstRow) {
    const auto* first = reinterpret_cast<const char*>(
        out.values +
        static_cast<size_t>(out.stride) * (out.image ? geometry_.pixels[firstRow] : firstRow));
    const auto* end = reinterpret_cast<const char*>(
        out.values +
        static_cast<size_t>(out.stride) * ((out.image ? geometry_.pixels[lastRow] : lastRow) + 1));
    for (const char* line = first; line < end; line += 64) __builtin_prefetch(line, 1, 3);
  }
  float shaded[3][kChunkRows];
  for (long long j = bandChunks_[band]; j < bandChunks_[band + 1]; ++j) {
    const int c = chunks_[j].cluster;
    kernels::shadeChunk(coefficients.data() + chunks_[j].coefficientOffset,
                        clusterLighting_.data() + 3 * lightingOffset_[c], activeRanks_[c],
                        meanTerm_.data() + 3 * c, shaded);
    const float* albedo = chunkAlbedo_.data() + j * 3 * kChunkRows;
    const bool consecutive =
        chunkConsecutive_[j] & (out.image ? kPixelsConsecutive : kRowsConsecutive);
    if (!out.image) {
      const std::int32_t* rows = chunkRows_.data() + j * kChunkRows;
      if (consecutive) {
        storeRows(shaded, albedo, out.values + 3 * static_cast<size_t>(rows[0]));
        continue;
      }
      for (int lane = 0; lane < kChunkRows; ++lane)
        if (rows[lane] >= 0)
          for (int ch = 0; ch < 3; ++ch)
            out.values[3 * rows[lane] + ch] = albedo[ch * kChunkRows + lane] * shaded[ch][lane];
    } else {
      const std::int32_t* pixels = chunkPixels_.data() + j * kChunkRows;
      const float* coverage = chunkCoverage_.data() + j * kChunkRows;
      if (consecutive) {  // relightInto allows 3 or 4 channels
        float* first = out.values + static_cast<size_t>(out.stride) * pixels[0];
        out.stride == 4 ? addPixels<4>(shaded, albedo, coverage, first)
                        : addPixels<3>(shaded, albedo, coverage, first);
        continue;
      }
      for (int lane = 0; lane < kChunkRows; ++lane)
        if (pixels[lane] >= 0)
          for (int ch = 0; ch < 3; ++ch)
            out.values[static_cast<size_t>(out.stride) * pixels[lane] + ch] +=
                coverage[lane] * (albedo[ch * kChunkRows + lane] * shaded[ch][lane]);
    }
  }
}

template <typename B, typename T>
void ModelRelighter::shadeAll(const HugePageVector<B>& bases, const HugePageVector<T>& coefficients,
                              const Output& out) {
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(ranks_.size()), 1),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int c = range.begin(); c != range.end(); ++c) lightCluster(c, bases);
                    });
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(bandChunks_.size()) - 1, 1),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int b = range.begin(); b != range.end(); ++b)
                        shadeBand(b, coefficients, out);
                    });
}

void ModelRelighter::shadeAll(const Output& out) {
  const auto withBases = [&](const auto& bases) {
    switch (precision_) {
      case CoeffPrecision::F32:
        return shadeAll(bases, coeffF32_, out);
      case CoeffPrecision::F16:
        return shadeAll(bases, coeffF16_, out);
      case CoeffPrecision::I8:
        return shadeAll(bases, coeffI8_, out);
    }
  };
  if (basisPrecision_ == CoeffPrecision::F16)
    withBases(basesF16_);
  else
    withBases(bases_);
}

void ModelRelighter::relight(const LatticeLighting& lighting, float* rgb) {
  lightGlobal(lighting);
  shadeAll({rgb, 3, false});
}

void ModelRelighter::relightInto(const LatticeLighting& lighting, float* pixels, int channels) {
  ACPCA_CHECK(channels == 3 || channels == 4, "channels ", channels);
  lightGlobal(lighting);
  shadeAll({pixels, channels, true});
}

std::vector<float> ModelRelighter::relight(const LatticeLighting& lighting) {
  std::vector<float> rgb(3 * rows());
  relight(lighting, rgb.data());
  return rgb;
}

}  // namespace acpca
