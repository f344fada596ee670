#include "relight/local_relight.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <numbers>

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

/// One cluster's rows and, per light, the groups of them that see it through
/// one set of direction taps: those found at the group's anchor (the mean of
/// its rows' positions). The row elements (texel, or channel x texel) the
/// taps touch that V_g sees, sorted.
struct ClusterLights {
  std::vector<std::int32_t> rows;                ///< in chunk order
  std::vector<size_t> lane;                      ///< per row: chunk index x 16 + lane
  std::vector<int> groupOf;                      ///< per light and row: light * rows + row
  std::vector<std::vector<LightTap>> groupTaps;  ///< per group, summing to 1
  std::vector<int> elements;
};

/// Rows of one cluster grouped for one light: in cubes of side `side` (rows
/// in one cube see the light within about side / distance of each other's
/// direction), each group in row order; side 0 gives every row a group.
std::vector<std::vector<size_t>> groupRows(const TransportHeader& h,
                                           const std::vector<std::int32_t>& rows, double side) {
  std::vector<std::vector<size_t>> groups;
  if (!(side > 0)) {
    for (size_t r = 0; r < rows.size(); ++r) groups.push_back({r});
    return groups;
  }
  using Key = std::array<long long, 3>;
  std::vector<std::pair<Key, size_t>> keyed;
  for (size_t r = 0; r < rows.size(); ++r) {
    const Vec3 p = positionOf(h, rows[r]);
    keyed.push_back({{static_cast<long long>(std::floor(p.x() / side)),
                      static_cast<long long>(std::floor(p.y() / side)),
                      static_cast<long long>(std::floor(p.z() / side))},
                     r});
  }
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) groups.emplace_back();
    groups.back().push_back(keyed[i].second);
  }
  return groups;
}

/// The side of the cubes a cluster's rows are grouped in for one light:
/// `spread` texels of direction at the distance of the cluster's nearest
/// point to the light (0: exact, one group per row).
double groupSide(const LocalLight& light, const TransportHeader& h,
                 const std::vector<std::int32_t>& rows, double spread, double texelAngle) {
  if (!(spread > 0) || rows.empty()) return 0;
  Eigen::AlignedBox3d box;
  for (std::int32_t row : rows) box.extend(positionOf(h, row));
  const double nearest = std::sqrt(box.squaredExteriorDistance(light.position));
  const double side = spread * texelAngle * nearest / std::sqrt(3.0);
  // Cube indices must fit: a light inside the box gets a group per row.
  return side > 1e-9 * box.diagonal().norm() ? side : 0;
}

/// Step 1 of modelLocalRelight for one cluster: per light its rows' groups,
/// each group's direction taps at its anchor, and the elements they touch.
void findGroupTaps(const TransportHeader& h, const CubeLattice& lattice,
                   const std::vector<LocalLight>& lights, const std::vector<int>& seenIndex,
                   double anchorSpread, ClusterLights& c) {
  const int l = h.latticeSize(), channels = h.channels;
  const double texelAngle = 0.5 * std::numbers::pi / h.cubemapResolution;
  c.groupOf.assign(lights.size() * c.rows.size(), -1);
  for (size_t li = 0; li < lights.size(); ++li) {
    const double side = groupSide(lights[li], h, c.rows, anchorSpread, texelAngle);
    for (const std::vector<size_t>& group : groupRows(h, c.rows, side)) {
      Vec3 anchor = Vec3::Zero();
      for (size_t r : group) anchor += positionOf(h, c.rows[r]);
      anchor /= static_cast<double>(group.size());
      std::vector<LightTap> taps;
      // An anchor among rows around a sphere may fall inside it: then a row's.
      if (!appendDirectionTaps(lights[li], lattice, anchor, taps))
        ACPCA_CHECK(
            appendDirectionTaps(lights[li], lattice, positionOf(h, c.rows[group.front()]), taps),
            lights[li].spec, " encloses a pixel");
      for (size_t r : group) c.groupOf[li * c.rows.size() + r] = int(c.groupTaps.size());
      for (const LightTap& t : taps)
        for (int ch = 0; ch < channels; ++ch)
          if (const int e = elementOf(ch, t.texel, channels, l); seenIndex[e] >= 0)
            c.elements.push_back(e);
      c.groupTaps.push_back(std::move(taps));
    }
  }
  std::sort(c.elements.begin(), c.elements.end());
  c.elements.erase(std::unique(c.elements.begin(), c.elements.end()), c.elements.end());
}

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

/// u . v over n values in float as eight interleaved sums added in a fixed
/// order: the compiler keeps them in SIMD lanes, and the result does not
/// depend on where the arrays lie (the same bytes in every process).
float dotInLanes(const float* u, const float* v, int n) {
  std::array<float, 8> sum{};
  int k = 0;
  for (; k + 8 <= n; k += 8)
    for (int i = 0; i < 8; ++i) sum[i] += u[k + i] * v[k + i];
  float tail = 0;
  for (; k < n; ++k) tail += u[k] * v[k];
  return ((sum[0] + sum[4]) + (sum[1] + sum[5])) + ((sum[2] + sum[6]) + (sum[3] + sum[7])) + tail;
}

/// The first `rank` coefficients of chunk j's 16 lanes as floats (i8 steps
/// applied), k-major as packed: block[k * 16 + lane].
void loadChunk(const PackedModel& m, size_t j, int rank, std::vector<float>& block) {
  const PackedModel::Chunk& chunk = m.chunks[j];
  const size_t count = static_cast<size_t>(rank) * kChunkRows;
  block.resize(count);
  const long long at = chunk.coefficientOffset;
  switch (m.precision) {
    case CoeffPrecision::F32:
      std::copy_n(m.coeffF32.data() + at, count, block.data());
      return;
    case CoeffPrecision::F16:
      halfToFloat(m.coeffF16.data() + at, block.data(), count);
      return;
    case CoeffPrecision::I8:
      for (size_t i = 0; i < count; ++i)
        block[i] = m.coeffI8[at + i] * m.scale[m.lightingOffset[chunk.cluster] + i / kChunkRows];
      return;
  }
}

/// Step 3 of modelLocalRelight for one cluster: each group's transport
/// towards its light per unit irradiance, W_c^T V_g^T (sum of taps) and
/// mu_c . V_g^T (sum of taps), rank + 1 values per group and channel of the
/// row. One float product per basis chunk either way, over whichever is
/// fewer: the texels the groups' taps touch (columns, then weighted sums of
/// them) or the groups (their taps summed in V_g's space first).
std::vector<double> groupTransport(const PackedModel& m, int cluster, int rank,
                                   const ClusterLights& c, const std::vector<float>& globalRows,
                                   const std::vector<int>& slotOf, std::vector<int>& columnOf) {
  const TransportHeader& h = m.geometry;
  const int n = m.globalBases, channels = h.channels, l = h.latticeSize(), stride = rank + 1;
  const size_t groupRows = c.groupTaps.size() * channels;
  const auto globalRow = [&](int e) {
    return Eigen::Map<const Eigen::VectorXf>(globalRows.data() + size_t(slotOf[e]) * n, n);
  };
  const bool byGroup = groupRows <= c.elements.size();
  RowMatrixF g = RowMatrixF::Zero(byGroup ? groupRows : c.elements.size(), n);
  if (byGroup) {
    for (size_t gi = 0; gi < c.groupTaps.size(); ++gi)
      for (const LightTap& t : c.groupTaps[gi])
        for (int ch = 0; ch < channels; ++ch)
          if (const int e = elementOf(ch, t.texel, channels, l); slotOf[e] >= 0)
            g.row(gi * channels + ch) += float(t.weight) * globalRow(e).transpose();
  } else {
    for (size_t i = 0; i < c.elements.size(); ++i) {
      g.row(i) = globalRow(c.elements[i]).transpose();
      columnOf[c.elements[i]] = static_cast<int>(i);
    }
  }
  const Eigen::MatrixXf columns = clusterColumns(m, cluster, rank, g);
  // mu_c . g per row, summed in index order: Eigen's matrix-vector product
  // splits its sums by the vectors' alignment, which differs between
  // processes, and the same inputs must give the same bytes.
  std::vector<double> meanTerm(g.rows(), 0.0);
  if (m.hasMean)
    for (Eigen::Index row = 0; row < g.rows(); ++row)
      for (int i = 0; i < n; ++i)
        meanTerm[row] += double(g(row, i)) * m.means[size_t(cluster) * n + i];
  std::vector<double> towards(groupRows * stride, 0.0);
  if (byGroup) {
    for (size_t row = 0; row < groupRows; ++row) {
      for (int k = 0; k < rank; ++k) towards[row * stride + k] = columns(k, row);
      towards[row * stride + rank] = meanTerm[row];
    }
    return towards;
  }
  for (size_t gi = 0; gi < c.groupTaps.size(); ++gi)
    for (const LightTap& t : c.groupTaps[gi])
      for (int ch = 0; ch < channels; ++ch) {
        const int column = columnOf[elementOf(ch, t.texel, channels, l)];
        if (column < 0) continue;  // a direction no pixel sees: zero in V_g
        double* v = towards.data() + (gi * channels + ch) * stride;
        for (int k = 0; k < rank; ++k) v[k] += t.weight * columns(k, column);
        v[rank] += t.weight * meanTerm[column];
      }
  for (int e : c.elements) columnOf[e] = -1;
  return towards;
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
                                     const std::vector<LocalLight>& lights, double anchorSpread) {
  const PackedModel& m = *relighter.packed();
  const TransportHeader& h = m.geometry;
  const CubeLattice lattice(h.cubemapResolution);
  const int channels = h.channels;
  std::vector<float> out(3 * static_cast<size_t>(m.rows()), 0.0f);
  if (lights.empty() || m.rows() == 0) return out;
  std::vector<int> seenIndex(h.rowLength(), -1);
  for (size_t i = 0; i < m.seenTexels.size(); ++i) seenIndex[m.seenTexels[i]] = static_cast<int>(i);

  // 1. Per cluster and light, its rows in groups, each group's direction taps
  //    at its anchor, and the elements the cluster needs.
  std::vector<ClusterLights> clusters(m.clusters());
  for (size_t j = 0; j < m.chunks.size(); ++j)
    for (int lane = 0; lane < kChunkRows; ++lane)
      if (const std::int32_t row = m.chunkRows[j * kChunkRows + lane]; row >= 0) {
        ClusterLights& c = clusters[m.chunks[j].cluster];
        c.rows.push_back(row);
        c.lane.push_back(j * kChunkRows + lane);
      }
  tbb::parallel_for(0, m.clusters(), [&](int cluster) {
    findGroupTaps(h, lattice, lights, seenIndex, anchorSpread, clusters[cluster]);
  });

  // 2. V_g's rows for every element some cluster needs.
  std::vector<int> slotOf(h.rowLength(), -1), seenOfSlot;
  for (const ClusterLights& c : clusters)
    for (int e : c.elements)
      if (slotOf[e] < 0) {
        slotOf[e] = static_cast<int>(seenOfSlot.size());
        seenOfSlot.push_back(seenIndex[e]);
      }
  const std::vector<float> globalRows = gatherGlobalRows(m, seenOfSlot);

  // 3. Per cluster each group's transport towards its light (groupTransport),
  //    then each row: the light's irradiance at the row's own position times
  //    its coefficients against its group's.
  tbb::enumerable_thread_specific<std::vector<int>> columnOfElement(h.rowLength(), -1);
  tbb::parallel_for(0, m.clusters(), [&](int cluster) {
    const ClusterLights& c = clusters[cluster];
    const int rank = relighter.activeRanks()[cluster];
    if (c.elements.empty() || (rank == 0 && !m.hasMean)) return;
    const int stride = rank + 1;
    const std::vector<double> towards =
        groupTransport(m, cluster, rank, c, globalRows, slotOf, columnOfElement.local());
    std::vector<float> block;
    const std::vector<float> towardsF(towards.begin(), towards.end());
    std::vector<float> u(rank);
    size_t loaded = static_cast<size_t>(-1);
    for (size_t r = 0; r < c.rows.size(); ++r) {
      const size_t chunk = c.lane[r] / kChunkRows;
      const int lane = static_cast<int>(c.lane[r] % kChunkRows);
      if (chunk != loaded) loadChunk(m, loaded = chunk, rank, block);
      for (int k = 0; k < rank; ++k) u[k] = block[k * kChunkRows + lane];
      const std::int32_t row = c.rows[r];
      const Vec3 at = positionOf(h, row);
      Rgb value = Rgb::Zero();
      for (size_t li = 0; li < lights.size(); ++li) {
        const double irradiance = lightIrradiance(lights[li], at);
        if (irradiance <= 0) continue;  // outside a spot's cone (enclosed: refused before)
        const size_t gi = c.groupOf[li * c.rows.size() + r];
        for (int ch = 0; ch < channels; ++ch) {
          const float* v = towardsF.data() + (gi * channels + ch) * stride;
          const double transport = v[rank] + dotInLanes(u.data(), v, rank);
          if (channels == 1)
            value += irradiance * transport * lights[li].emission;
          else
            value[ch] += irradiance * transport * lights[li].emission[ch];
        }
      }
      for (int ch = 0; ch < 3; ++ch)
        out[3 * static_cast<size_t>(row) + ch] =
            static_cast<float>(h.albedo[3 * row + ch] * value[ch]);
    }
  });
  return out;
}

}  // namespace acpca
