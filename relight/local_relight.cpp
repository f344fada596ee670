#include "relight/local_relight.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/half.h"
#include "relight/relight_kernels.h"
#include "transport/row_stream.h"

namespace acpca {

namespace {

using kernels::kChunkRows;

/// One texel of a pixel's local lighting, all lights summed: radiance x solid
/// angle per channel.
struct ColourTap {
  int texel;
  Rgb weight;
};

Vec3 positionOf(const TransportHeader& h, long long row) {
  return {h.positions[3 * row], h.positions[3 * row + 1], h.positions[3 * row + 2]};
}

/// The lights seen from `point` as coloured taps (a texel may repeat).
void colourTaps(const std::vector<LocalLight>& lights, const CubeLattice& lattice,
                const Vec3& point, std::vector<LightTap>& scratch, std::vector<ColourTap>& taps) {
  taps.clear();
  for (const LocalLight& light : lights) {
    scratch.clear();
    // requireLocalLightsApply refused lights that enclose a pixel's position.
    ACPCA_CHECK(appendLightTaps(light, lattice, point, scratch), light.spec, " encloses a pixel");
    for (const LightTap& t : scratch) taps.push_back({t.texel, t.weight * light.emission});
  }
}

/// Where channel c of texel j sits in a row of `channels` x l values.
int elementOf(int channel, int texel, int channels, int l) {
  return (channels == 3 ? channel * l : 0) + texel;
}

std::string pixelName(const TransportHeader& h, long long row) {
  const int width = h.camera.size.width;
  return concat("(", h.pixels[row] % width, ", ", h.pixels[row] / width, ")");
}

/// A cluster's reconstruction of T at the row elements its pixels' lights
/// touch, one column (W_c^T V_g^T e, then mu_c . V_g^T e) per element, made
/// when first asked for.
class ClusterColumns {
 public:
  ClusterColumns(const PackedModel& m, const std::vector<int>& seenIndex)
      : m_(m), seenIndex_(seenIndex), slotOf_(seenIndex.size(), -1) {}

  /// Starts cluster c with its first `rank` bases; forgets the last one's columns.
  void start(int cluster, int rank) {
    for (int e : used_) slotOf_[e] = -1;
    used_.clear();
    columns_.clear();
    cluster_ = cluster;
    rank_ = rank;
  }

  /// The column of element e (rank_ + 1 values), or null when no pixel sees it.
  const double* column(int e) {
    if (slotOf_[e] >= 0) return columns_.data() + static_cast<size_t>(slotOf_[e]) * (rank_ + 1);
    const int seen = seenIndex_[e];
    if (seen < 0) return nullptr;
    const size_t at = columns_.size();
    slotOf_[e] = static_cast<int>(at / (rank_ + 1));
    used_.push_back(e);
    columns_.resize(at + rank_ + 1, 0.0);
    const int n = m_.globalBases;
    const long long seenCount = static_cast<long long>(m_.seenTexels.size());
    const long long basis = m_.basisOffset[cluster_];
    for (int g = 0; g < n; ++g) {
      const double v = m_.globalBasis[g * seenCount + seen];  // V_g[e, g]
      if (v == 0) continue;
      for (int k = 0; k < rank_; ++k) {
        const long long w = basis + (k / kChunkRows) * kChunkRows * n + g * kChunkRows +
                            k % kChunkRows;  // W_c[g, k], packed_model.h
        columns_[at + k] += v * basisValue(w);
      }
      if (m_.hasMean) columns_[at + rank_] += v * m_.means[static_cast<size_t>(cluster_) * n + g];
    }
    return columns_.data() + at;
  }

 private:
  double basisValue(long long i) const {
    if (m_.basisPrecision != CoeffPrecision::F16) return m_.bases[i];
    float f;
    halfToFloat(&m_.basesF16[i], &f, 1);
    return f;
  }

  const PackedModel& m_;
  const std::vector<int>& seenIndex_;
  std::vector<int> slotOf_;
  std::vector<int> used_;
  std::vector<double> columns_;
  int cluster_ = 0, rank_ = 0;
};

/// Coefficient k of lane `lane` of chunk j, as a float (i8 steps applied).
double coefficient(const PackedModel& m, size_t j, int k, int lane) {
  const PackedModel::Chunk& chunk = m.chunks[j];
  const long long i = chunk.coefficientOffset + static_cast<long long>(k) * kChunkRows + lane;
  switch (m.precision) {
    case CoeffPrecision::F32:
      return m.coeffF32[i];
    case CoeffPrecision::F16: {
      float f;
      halfToFloat(&m.coeffF16[i], &f, 1);
      return f;
    }
    case CoeffPrecision::I8:
      return m.coeffI8[i] * double(m.scale[m.lightingOffset[chunk.cluster] + k]);
  }
  return 0;
}

}  // namespace

void requireLocalLightsApply(const TransportHeader& header, const std::string& path, bool model,
                             const std::vector<LocalLight>& lights) {
  if (lights.empty()) return;
  if (!header.hasPositions())
    throw UserError(
        concat(path,
               ": has no pixel positions, which local lights need (it was written before they were "
               "stored); ",
               model ? "precompute its transport again and compress (or build) it again"
                     : "precompute it again"));
  const CubeLattice lattice(header.cubemapResolution);
  std::vector<LightTap> taps;
  for (const LocalLight& light : lights) {
    long long inside = 0, first = -1;
    for (long long row = 0; row < header.rows(); ++row) {
      const Vec3 d = light.position - positionOf(header, row);
      const double reach = light.kind == LocalLightKind::Sphere ? light.radius : 0.0;
      if (d.squaredNorm() <= reach * reach) {
        if (inside++ == 0) first = row;
      }
    }
    if (inside > 0)
      throw ParameterError(
          "light", light.spec,
          concat(light.kind == LocalLightKind::Sphere ? "encloses " : "sits on ", inside,
                 " pixel position(s) of ", path, ", the first at pixel ", pixelName(header, first),
                 ": a local light must lie off the surfaces it lights; move it",
                 light.kind == LocalLightKind::Sphere ? " or make it smaller" : ""));
  }
}

std::vector<float> denseLocalRelight(const TransportReader& transport,
                                     const std::vector<LocalLight>& lights) {
  const TransportHeader& h = transport.header();
  requireLocalLightsApply(h, transport.path(), false, lights);
  const CubeLattice lattice(h.cubemapResolution);
  const int l = transport.latticeSize(), length = transport.rowLength();
  std::vector<float> out(3 * static_cast<size_t>(transport.rows()), 0.0f);
  if (lights.empty() || transport.rows() == 0) return out;
  streamRowBlocks(
      transport, rowsPerBlock(transport), [&](long long first, long long count, const float* rows) {
        tbb::parallel_for(tbb::blocked_range<long long>(0, count, 32), [&](const auto& range) {
          std::vector<LightTap> scratch;
          std::vector<ColourTap> taps;
          for (long long r = range.begin(); r < range.end(); ++r) {
            const long long row = first + r;
            colourTaps(lights, lattice, positionOf(h, row), scratch, taps);
            const float* t = rows + r * length;
            for (int c = 0; c < 3; ++c) {
              double value = 0;
              for (const ColourTap& tap : taps)
                value += tap.weight[c] * t[elementOf(c, tap.texel, h.channels, l)];
              out[3 * row + c] = static_cast<float>(h.albedo[3 * row + c] * value);
            }
          }
        });
      });
  return out;
}

std::vector<float> modelLocalRelight(const ModelRelighter& relighter,
                                     const std::vector<LocalLight>& lights) {
  const PackedModel& m = *relighter.packed();
  const TransportHeader& h = m.geometry;
  const CubeLattice lattice(h.cubemapResolution);
  const int l = h.latticeSize();
  std::vector<float> out(3 * static_cast<size_t>(m.rows()), 0.0f);
  if (lights.empty() || m.rows() == 0) return out;
  std::vector<int> seenIndex(h.rowLength(), -1);
  for (size_t i = 0; i < m.seenTexels.size(); ++i) seenIndex[m.seenTexels[i]] = static_cast<int>(i);
  std::vector<std::vector<size_t>> chunksOf(m.clusters());
  for (size_t j = 0; j < m.chunks.size(); ++j) chunksOf[m.chunks[j].cluster].push_back(j);

  tbb::enumerable_thread_specific<ClusterColumns> columnsOf(m, seenIndex);
  tbb::parallel_for(0, m.clusters(), [&](int cluster) {
    ClusterColumns& columns = columnsOf.local();
    const int rank = relighter.activeRanks()[cluster];
    columns.start(cluster, rank);
    std::vector<LightTap> scratch;
    std::vector<ColourTap> taps;
    std::vector<double> u(rank);
    for (size_t j : chunksOf[cluster])
      for (int lane = 0; lane < kChunkRows; ++lane) {
        const long long row = m.chunkRows[j * kChunkRows + lane];
        if (row < 0) continue;
        colourTaps(lights, lattice, positionOf(h, row), scratch, taps);
        for (int k = 0; k < rank; ++k) u[k] = coefficient(m, j, k, lane);
        for (int c = 0; c < 3; ++c) {
          double value = 0;
          for (const ColourTap& tap : taps) {
            const double* column = columns.column(elementOf(c, tap.texel, h.channels, l));
            if (!column) continue;  // a direction no pixel sees: zero in V_g
            double t = column[rank];
            for (int k = 0; k < rank; ++k) t += u[k] * column[k];
            value += tap.weight[c] * t;
          }
          out[3 * row + c] = static_cast<float>(h.albedo[3 * row + c] * value);
        }
      }
  });
  return out;
}

}  // namespace acpca
