#include "relight/local_relight.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <algorithm>

#include "core/error.h"
#include "core/half.h"
#include "relight/relight_kernels.h"
#include "transport/row_stream.h"

namespace acpca {

namespace {

using kernels::kChunkRows;
using RowMatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

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

/// One cluster's rows with the taps of their lights, and the row elements
/// (texel, or channel x texel) those taps touch that V_g sees, sorted.
struct ClusterTaps {
  std::vector<std::int32_t> rows;  ///< in chunk order
  std::vector<size_t> lane;        ///< per row: chunk index x 16 + lane
  std::vector<size_t> tapStart;    ///< per row, and one past the last
  std::vector<ColourTap> taps;
  std::vector<int> elements;
};

/// V_g's rows for the given elements, row by row (elements x N): one pass over
/// V_g, which is stored global basis by global basis.
std::vector<float> gatherGlobalRows(const PackedModel& m, const std::vector<int>& seenOfSlot) {
  const int n = m.globalBases;
  const long long seen = static_cast<long long>(m.seenTexels.size());
  std::vector<float> rows(seenOfSlot.size() * n);
  tbb::parallel_for(0, n, [&](int g) {
    for (size_t slot = 0; slot < seenOfSlot.size(); ++slot)
      rows[slot * n + g] = m.globalBasis[g * seen + seenOfSlot[slot]];
  });
  return rows;
}

/// W_c^T G^T for a cluster's first `rank` bases (rank x |G| values, column
/// by column): one product per basis chunk of 16, as packed_model.h stores them.
Eigen::MatrixXf clusterColumns(const PackedModel& m, int cluster, int rank,
                               const Eigen::Ref<const RowMatrixF>& g) {
  const int n = m.globalBases;
  Eigen::MatrixXf columns(rank, g.rows());
  std::vector<float> chunk;
  for (int first = 0; first < rank; first += kChunkRows) {
    const long long at = m.basisOffset[cluster] + static_cast<long long>(first) * n;
    const float* values = nullptr;
    if (m.basisPrecision == CoeffPrecision::F16) {
      chunk.resize(static_cast<size_t>(n) * kChunkRows);
      halfToFloat(m.basesF16.data() + at, chunk.data(), chunk.size());
      values = chunk.data();
    } else {
      values = m.bases.data() + at;
    }
    const Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, kChunkRows, Eigen::RowMajor>> w(
        values, n, kChunkRows);
    const int count = std::min(kChunkRows, rank - first);
    columns.middleRows(first, count).noalias() = w.leftCols(count).transpose() * g.transpose();
  }
  return columns;
}

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
  const int l = h.latticeSize(), n = m.globalBases;
  std::vector<float> out(3 * static_cast<size_t>(m.rows()), 0.0f);
  if (lights.empty() || m.rows() == 0) return out;
  std::vector<int> seenIndex(h.rowLength(), -1);
  for (size_t i = 0; i < m.seenTexels.size(); ++i) seenIndex[m.seenTexels[i]] = static_cast<int>(i);

  // 1. Every row's taps, cluster by cluster, and the elements each cluster needs.
  std::vector<ClusterTaps> clusters(m.clusters());
  for (size_t j = 0; j < m.chunks.size(); ++j)
    for (int lane = 0; lane < kChunkRows; ++lane)
      if (const std::int32_t row = m.chunkRows[j * kChunkRows + lane]; row >= 0) {
        ClusterTaps& c = clusters[m.chunks[j].cluster];
        c.rows.push_back(row);
        c.lane.push_back(j * kChunkRows + lane);
      }
  tbb::parallel_for(0, m.clusters(), [&](int cluster) {
    ClusterTaps& c = clusters[cluster];
    std::vector<LightTap> scratch;
    std::vector<ColourTap> taps;
    for (std::int32_t row : c.rows) {
      c.tapStart.push_back(c.taps.size());
      colourTaps(lights, lattice, positionOf(h, row), scratch, taps);
      c.taps.insert(c.taps.end(), taps.begin(), taps.end());
      for (const ColourTap& t : taps)
        for (int ch = 0; ch < h.channels; ++ch)
          if (const int e = elementOf(ch, t.texel, h.channels, l); seenIndex[e] >= 0)
            c.elements.push_back(e);
    }
    c.tapStart.push_back(c.taps.size());
    std::sort(c.elements.begin(), c.elements.end());
    c.elements.erase(std::unique(c.elements.begin(), c.elements.end()), c.elements.end());
  });

  // 2. V_g's rows for every element some cluster needs.
  std::vector<int> slotOf(h.rowLength(), -1), seenOfSlot;
  for (const ClusterTaps& c : clusters)
    for (int e : c.elements)
      if (slotOf[e] < 0) {
        slotOf[e] = static_cast<int>(seenOfSlot.size());
        seenOfSlot.push_back(seenIndex[e]);
      }
  const std::vector<float> globalRows = gatherGlobalRows(m, seenOfSlot);

  // 3. Per cluster its columns (W_c^T V_g^T e and mu_c . V_g^T e per element),
  //    then each row: its coefficients against the columns of its taps.
  tbb::enumerable_thread_specific<std::vector<int>> columnOfElement(h.rowLength(), -1);
  tbb::parallel_for(0, m.clusters(), [&](int cluster) {
    const ClusterTaps& c = clusters[cluster];
    const int rank = relighter.activeRanks()[cluster];
    if (c.elements.empty() || (rank == 0 && !m.hasMean)) return;
    RowMatrixF g(c.elements.size(), n);
    std::vector<int>& columnOf = columnOfElement.local();
    for (size_t i = 0; i < c.elements.size(); ++i) {
      std::copy_n(globalRows.data() + static_cast<size_t>(slotOf[c.elements[i]]) * n, n,
                  g.row(i).data());
      columnOf[c.elements[i]] = static_cast<int>(i);
    }
    const Eigen::MatrixXf columns = clusterColumns(m, cluster, rank, g);
    Eigen::VectorXf meanTerm = Eigen::VectorXf::Zero(g.rows());
    if (m.hasMean)
      meanTerm = g * Eigen::Map<const Eigen::VectorXf>(m.means.data() + size_t(cluster) * n, n);
    std::vector<double> u(rank);
    for (size_t r = 0; r < c.rows.size(); ++r) {
      const size_t chunk = c.lane[r] / kChunkRows;
      const int lane = static_cast<int>(c.lane[r] % kChunkRows);
      for (int k = 0; k < rank; ++k) u[k] = coefficient(m, chunk, k, lane);
      const std::int32_t row = c.rows[r];
      Rgb value = Rgb::Zero();
      for (size_t t = c.tapStart[r]; t < c.tapStart[r + 1]; ++t)
        for (int ch = 0; ch < h.channels; ++ch) {  // one row serves R, G and B, or one each
          const int column = columnOf[elementOf(ch, c.taps[t].texel, h.channels, l)];
          if (column < 0) continue;  // a direction no pixel sees: zero in V_g
          double transport = meanTerm[column];
          for (int k = 0; k < rank; ++k) transport += u[k] * columns(k, column);
          if (h.channels == 1)
            value += transport * c.taps[t].weight;
          else
            value[ch] += transport * c.taps[t].weight[ch];
        }
      for (int ch = 0; ch < 3; ++ch)
        out[3 * static_cast<size_t>(row) + ch] =
            static_cast<float>(h.albedo[3 * row + ch] * value[ch]);
    }
    for (int e : c.elements) columnOf[e] = -1;
  });
  return out;
}

}  // namespace acpca
