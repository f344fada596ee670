#include "relight/model_relighter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "relight/rank_limit.h"
#include "relight/relight_kernels.h"

namespace acpca {

using kernels::kChunkRows;

namespace {

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

}  // namespace

ModelRelighter::ModelRelighter(const Model& model)
    : ModelRelighter(std::make_shared<const PackedModel>(model)) {}

ModelRelighter::ModelRelighter(std::shared_ptr<const PackedModel> packed)
    : packed_(std::move(packed)),
      m_(*packed_),
      activeRanks_(m_.ranks),
      // Every frame's light at the same alignment (64 bytes), so each frame's
      // sums are the same whichever place in a group it takes.
      lightStride_((3 * m_.seenTexels.size() + 15) / 16 * 16) {
  reserveGroup(1);
}

void ModelRelighter::setMaxRank(int k) {
  activeRanks_ = ranksUpTo(m_.ranks, k);
}

void ModelRelighter::setRankFraction(double fraction) {
  activeRanks_ = ranksOfFraction(m_.ranks, fraction);
}

long long ModelRelighter::bytesPerFrame(size_t groupFrames) const {
  const long long elementBytes = storedBytes(m_.precision);
  const long long basisBytes = storedBytes(m_.basisPrecision);
  // V_g, the bases and the means: read once a group.
  long long shared = static_cast<long long>(m_.globalBasis.size()) * 4;
  for (size_t c = 0; c < activeRanks_.size(); ++c)
    shared += (activeRanks_[c] + kChunkRows - 1) / kChunkRows * kChunkRows *
                  static_cast<long long>(m_.globalBases) * basisBytes +
              (m_.hasMean ? m_.globalBases * 4LL : 0);
  long long bytes = shared / static_cast<long long>(std::max<size_t>(1, groupFrames));
  for (const PackedModel::Chunk& chunk : m_.chunks)
    bytes += activeRanks_[chunk.cluster] * kChunkRows * elementBytes;
  // Row indices and albedo of every chunk.
  bytes += static_cast<long long>(m_.chunks.size()) * kChunkRows * (4 + 12);
  return bytes;
}

double ModelRelighter::costPerPixel() const {
  // V_g^T L, in multiply-adds of RGB triples: with R, G and B rows each value
  // meets one channel, so three of them make one triple.
  double cost = static_cast<double>(m_.globalBasis.size()) / m_.geometry.channels;
  std::vector<long long> rowsOf(activeRanks_.size(), 0);
  for (const PackedModel::Chunk& chunk : m_.chunks) rowsOf[chunk.cluster] += kChunkRows;
  for (size_t c = 0; c < activeRanks_.size(); ++c)
    cost += (activeRanks_[c] + (m_.hasMean ? 1 : 0)) * double(m_.globalBases) +
            activeRanks_[c] * double(std::min<long long>(rowsOf[c], rows()));
  return rows() ? cost / rows() : 0;
}

void ModelRelighter::reserveGroup(size_t frames) {
  if (frames <= groupCapacity_) return;
  groupCapacity_ = frames;
  const size_t n = static_cast<size_t>(m_.globalBases);
  light_.assign(frames * lightStride_, 0.0f);
  globalLighting_.assign(frames * 3 * n, 0.0f);
  globalLightingRgb_.assign(frames * 3 * n, 0.0f);
  clusterLighting_.assign(frames * 3 * m_.totalRank, 0.0f);
  meanTerm_.assign(frames * 3 * static_cast<size_t>(m_.clusters()), 0.0f);
}

void ModelRelighter::lightGlobal(const LatticeLighting* const* lightings, size_t frames) {
  const long long l = m_.geometry.latticeSize();
  const int n = m_.globalBases;
  const int seen = static_cast<int>(m_.seenTexels.size());
  // With R, G and B rows side by side, channel c's light meets only the c-th
  // third of V_g's rows (row_layout.h).
  const bool rgbRows = m_.geometry.channels == 3;
  for (size_t g = 0; g < frames; ++g) {
    const LatticeLighting& lighting = *lightings[g];
    ACPCA_CHECK(static_cast<long long>(lighting.size()) == 3 * l, "lighting has ", lighting.size(),
                " values for a lattice of ", l);
    float* light = light_.data() + g * lightStride_;
    for (int i = 0; i < seen; ++i) {
      const long long j = m_.seenTexels[i] % l, part = m_.seenTexels[i] / l;
      for (int c = 0; c < 3; ++c)
        light[c * seen + i] =
            !rgbRows || c == part ? static_cast<float>(lighting[3 * j + c]) : 0.0f;
    }
  }
  // L_g = V_g^T L (as n x 3 interleaved, and split by channel), in fixed
  // blocks of 16 columns so each column's summation order never depends on how
  // TBB splits the work. A block's columns (16 x |seen| values) stay in cache
  // while every lighting of the group meets them: V_g is read once a group.
  constexpr int kBlock = 16;
  tbb::parallel_for(0, (n + kBlock - 1) / kBlock, [&](int block) {
    const int first = block * kBlock, count = std::min(kBlock, n - first);
    float out[3 * kBlock];
    for (size_t g = 0; g < frames; ++g) {
      const float* base = light_.data() + g * lightStride_;
      const float* light[3] = {base, base + seen, base + 2 * seen};
      if (rgbRows) {
        // Each channel meets its own third of the column alone: seenTexels is
        // sorted, so that third is one run [partStart[c], partStart[c + 1]).
        for (int k = 0; k < count; ++k)
          for (int c = 0; c < 3; ++c) {
            const int begin = m_.partStart[c], length = m_.partStart[c + 1] - begin;
            using Vec = Eigen::Map<const Eigen::VectorXf>;
            out[3 * k + c] =
                length > 0
                    ? Vec(m_.globalBasis.data() + static_cast<size_t>(first + k) * seen + begin,
                          length)
                          .dot(Vec(light[c] + begin, length))
                    : 0.0f;
          }
      } else {
        kernels::dotRgbColumns(m_.globalBasis.data() + static_cast<size_t>(first) * seen, count,
                               light, seen, out);
      }
      float* lg = globalLighting_.data() + g * 3 * n;
      float* lgRgb = globalLightingRgb_.data() + g * 3 * n;
      for (int k = 0; k < count; ++k)
        for (int c = 0; c < 3; ++c) {
          lg[c * n + first + k] = out[3 * k + c];
          lgRgb[3 * (first + k) + c] = out[3 * k + c];
        }
    }
  });
}

/// L_i = W_i^T L_g (the i8 step folded in) and the mean term mu_i . L_g, for
/// every frame of the group: each basis chunk (16 bases x N values) stays in
/// cache while the group's lightings meet it, so the bases are read once a group.
template <typename B>
void ModelRelighter::lightCluster(int c, const HugePageVector<B>& bases, size_t frames) {
  const int n = m_.globalBases;
  const size_t totalRank = static_cast<size_t>(m_.totalRank);
  const float zero[3] = {0, 0, 0};
  float lanes[3][kChunkRows];  // 16 bases of the basis chunk
  for (int first = 0; first < activeRanks_[c]; first += kChunkRows)
    for (size_t g = 0; g < frames; ++g) {
      kernels::shadeChunk(bases.data() + m_.basisOffset[c] + static_cast<size_t>(first) * n,
                          globalLightingRgb_.data() + g * 3 * n, n, zero, lanes);
      float* li = clusterLighting_.data() + 3 * (g * totalRank + m_.lightingOffset[c]);
      for (int k = first; k < std::min(first + kChunkRows, activeRanks_[c]); ++k)
        for (int ch = 0; ch < 3; ++ch)
          li[3 * k + ch] = lanes[ch][k - first] * m_.scale[m_.lightingOffset[c] + k];
    }
  for (size_t g = 0; g < frames; ++g) {
    float* mean = meanTerm_.data() + 3 * (g * m_.clusters() + c);
    const float* lgBase = globalLighting_.data() + g * 3 * n;
    const float* lg[3] = {lgBase, lgBase + n, lgBase + 2 * n};
    if (m_.hasMean)
      kernels::dotRgb(m_.means.data() + size_t(c) * n, lg, n, mean);
    else
      mean[0] = mean[1] = mean[2] = 0;
  }
}

template <typename B>
void ModelRelighter::lightClusters(const HugePageVector<B>& bases, size_t frames) {
  tbb::parallel_for(tbb::blocked_range<int>(0, m_.clusters(), 1),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int c = range.begin(); c != range.end(); ++c)
                        lightCluster(c, bases, frames);
                    });
}

/// Every chunk of one span: u_p . L_i times albedo (eq. 17).
template <typename T>
void ModelRelighter::shadeSpan(long long span, const HugePageVector<T>& coefficients,
                               const Output& out, size_t frame) const {
  const float* clusterLighting = clusterLighting_.data() + 3 * frame * m_.totalRank;
  const float* meanTerm = meanTerm_.data() + 3 * frame * m_.clusters();
  // Every output line of the span is written this frame, and none is in cache
  // any more (a frame streams far more than the caches hold): ask for them all
  // for writing now, in order, instead of one cache miss per chunk later.
  const long long firstRow = span * kSpanRows, lastRow = std::min(rows(), firstRow + kSpanRows) - 1;
  if (lastRow >= firstRow) {
    const auto* first = reinterpret_cast<const char*>(
        out.values +
        static_cast<size_t>(out.stride) * (out.image ? m_.geometry.pixels[firstRow] : firstRow));
    const auto* end = reinterpret_cast<const char*>(
        out.values + static_cast<size_t>(out.stride) *
                         ((out.image ? m_.geometry.pixels[lastRow] : lastRow) + 1));
    for (const char* line = first; line < end; line += 64) __builtin_prefetch(line, 1, 3);
  }
  float shaded[3][kChunkRows];
  for (long long j = m_.spanChunks[span]; j < m_.spanChunks[span + 1]; ++j) {
    const int c = m_.chunks[j].cluster;
    kernels::shadeChunk(coefficients.data() + m_.chunks[j].coefficientOffset,
                        clusterLighting + 3 * m_.lightingOffset[c], activeRanks_[c],
                        meanTerm + 3 * c, shaded);
    const float* albedo = m_.chunkAlbedo.data() + j * 3 * kChunkRows;
    const bool consecutive =
        m_.chunkConsecutive[j] & (out.image ? kPixelsConsecutive : kRowsConsecutive);
    if (!out.image) {
      const std::int32_t* rows = m_.chunkRows.data() + j * kChunkRows;
      if (consecutive) {
        storeRows(shaded, albedo, out.values + 3 * static_cast<size_t>(rows[0]));
        continue;
      }
      for (int lane = 0; lane < kChunkRows; ++lane)
        if (rows[lane] >= 0)
          for (int ch = 0; ch < 3; ++ch)
            out.values[3 * rows[lane] + ch] = albedo[ch * kChunkRows + lane] * shaded[ch][lane];
    } else {
      const std::int32_t* pixels = m_.chunkPixels.data() + j * kChunkRows;
      const float* coverage = m_.chunkCoverage.data() + j * kChunkRows;
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

template <typename T>
void ModelRelighter::shadeSpans(const HugePageVector<T>& coefficients, const Output& out,
                                size_t frame) const {
  tbb::parallel_for(tbb::blocked_range<long long>(0, m_.spans(), 1),
                    [&](const tbb::blocked_range<long long>& range) {
                      for (long long s = range.begin(); s != range.end(); ++s)
                        shadeSpan(s, coefficients, out, frame);
                    });
}

void ModelRelighter::shadeFrame(size_t frame, const Output& out) const {
  ACPCA_CHECK(frame < groupFrames_, "frame ", frame, " of a group of ", groupFrames_);
  switch (m_.precision) {
    case CoeffPrecision::F32:
      return shadeSpans(m_.coeffF32, out, frame);
    case CoeffPrecision::F16:
      return shadeSpans(m_.coeffF16, out, frame);
    case CoeffPrecision::I8:
      return shadeSpans(m_.coeffI8, out, frame);
  }
}

void ModelRelighter::lightGroup(const LatticeLighting* const* lightings, size_t frames) {
  reserveGroup(frames);
  groupFrames_ = 0;
  lightGlobal(lightings, frames);
  if (m_.basisPrecision == CoeffPrecision::F16)
    lightClusters(m_.basesF16, frames);
  else
    lightClusters(m_.bases, frames);
  groupFrames_ = frames;
}

void ModelRelighter::lightGroup(const std::vector<LatticeLighting>& lightings) {
  std::vector<const LatticeLighting*> pointers;
  for (const auto& l : lightings) pointers.push_back(&l);
  lightGroup(pointers.data(), pointers.size());
}

void ModelRelighter::shadeFrame(size_t frame, float* rgb) const {
  shadeFrame(frame, Output{rgb, 3, false});
}

void ModelRelighter::shadeFrameInto(size_t frame, float* pixels, int channels) const {
  ACPCA_CHECK(channels == 3 || channels == 4, "channels ", channels);
  shadeFrame(frame, Output{pixels, channels, true});
}

void ModelRelighter::relight(const LatticeLighting& lighting, float* rgb) {
  const LatticeLighting* one = &lighting;
  lightGroup(&one, 1);
  shadeFrame(0, rgb);
}

void ModelRelighter::relightInto(const LatticeLighting& lighting, float* pixels, int channels) {
  const LatticeLighting* one = &lighting;
  lightGroup(&one, 1);
  shadeFrameInto(0, pixels, channels);
}

std::vector<float> ModelRelighter::relight(const LatticeLighting& lighting) {
  std::vector<float> rgb(3 * rows());
  relight(lighting, rgb.data());
  return rgb;
}

}  // namespace acpca
