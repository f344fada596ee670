#include "relight/local_relight.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <climits>
#include <numbers>
#include <span>

#include "core/error.h"
#include "relight/local_columns.h"
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
  std::span<const std::int32_t> rows;            ///< in chunk order
  std::span<const size_t> lane;                  ///< per row: chunk index x 16 + lane
  std::vector<int> groupOf;                      ///< per light and row: light * rows + row
  std::vector<std::vector<LightTap>> groupTaps;  ///< per group, summing to 1
  std::vector<int> elements;
};

/// Rows of one cluster grouped for one light, as `order` (row indices, group
/// by group, each group in row order) and `starts` (each group's first place
/// in order, then the end): in cubes of side `side` (rows in one cube see the
/// light within about side / distance of each other's direction); side 0
/// gives every row a group.
void groupRows(const TransportHeader& h, std::span<const std::int32_t> rows, double side,
               std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& starts) {
  order.resize(rows.size());
  starts.clear();
  if (!(side > 0)) {
    for (size_t r = 0; r <= rows.size(); ++r) {
      if (r < rows.size()) order[r] = static_cast<std::uint32_t>(r);
      starts.push_back(static_cast<std::uint32_t>(r));
    }
    return;
  }
  // Cube indices relative to the lowest, packed in 21 bits each: one integer
  // key per row.
  std::vector<std::array<long long, 3>> cube(rows.size());
  std::array<long long, 3> low{LLONG_MAX, LLONG_MAX, LLONG_MAX},
      high{LLONG_MIN, LLONG_MIN, LLONG_MIN};
  for (size_t r = 0; r < rows.size(); ++r) {
    const Vec3 p = positionOf(h, rows[r]);
    for (int a = 0; a < 3; ++a) {
      cube[r][a] = static_cast<long long>(std::floor(p[a] / side));
      low[a] = std::min(low[a], cube[r][a]);
      high[a] = std::max(high[a], cube[r][a]);
    }
  }
  constexpr long long kSpan = 1LL << 21;
  for (int a = 0; a < 3; ++a)
    if (high[a] - low[a] >= kSpan) {  // too many cubes to pack: a group per row
      groupRows(h, rows, 0, order, starts);
      return;
    }
  // Groups numbered as their first rows come (an open-addressing table of
  // cube keys), then rows placed group by group in row order: no sort.
  size_t capacity = 16;
  while (capacity < 2 * rows.size()) capacity *= 2;
  constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::vector<std::uint64_t> slotKey(capacity, kEmpty);
  std::vector<std::uint32_t> slotGroup(capacity), groupOf(rows.size()), size;
  for (size_t r = 0; r < rows.size(); ++r) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) key = (key << 21) | static_cast<std::uint64_t>(cube[r][a] - low[a]);
    size_t at = static_cast<size_t>((key * 0x9E3779B97F4A7C15ULL) >> 20) & (capacity - 1);
    while (slotKey[at] != kEmpty && slotKey[at] != key) at = (at + 1) & (capacity - 1);
    if (slotKey[at] == kEmpty) {
      slotKey[at] = key;
      slotGroup[at] = static_cast<std::uint32_t>(size.size());
      size.push_back(0);
    }
    groupOf[r] = slotGroup[at];
    ++size[groupOf[r]];
  }
  starts.assign(1, 0);
  for (std::uint32_t n : size) starts.push_back(starts.back() + n);
  std::vector<std::uint32_t> next(starts.begin(), starts.end() - 1);
  for (size_t r = 0; r < rows.size(); ++r)
    order[next[groupOf[r]]++] = static_cast<std::uint32_t>(r);
}

/// The side of the cubes a cluster's rows are grouped in for one light:
/// `spread` texels of direction at the distance of the cluster's nearest
/// point to the light (0: exact, one group per row).
double groupSide(const LocalLight& light, const TransportHeader& h,
                 std::span<const std::int32_t> rows, double spread, double texelAngle) {
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
  std::vector<std::uint32_t> order, starts;
  for (size_t li = 0; li < lights.size(); ++li) {
    const double side = groupSide(lights[li], h, c.rows, anchorSpread, texelAngle);
    groupRows(h, c.rows, side, order, starts);
    for (size_t gi = 0; gi + 1 < starts.size(); ++gi) {
      const auto group = std::span(order).subspan(starts[gi], starts[gi + 1] - starts[gi]);
      Vec3 anchor = Vec3::Zero();
      for (std::uint32_t r : group) anchor += positionOf(h, c.rows[r]);
      anchor /= static_cast<double>(group.size());
      std::vector<LightTap> taps;
      // An anchor among rows around a sphere may fall inside it: then a row's.
      if (!appendDirectionTaps(lights[li], lattice, anchor, taps))
        ACPCA_CHECK(
            appendDirectionTaps(lights[li], lattice, positionOf(h, c.rows[group.front()]), taps),
            lights[li].spec, " encloses a pixel");
      for (std::uint32_t r : group) c.groupOf[li * c.rows.size() + r] = int(c.groupTaps.size());
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

/// Step 2 of modelLocalRelight for one cluster: each group's transport
/// towards its light per unit irradiance, W_c^T V_g^T (sum of taps) and
/// mu_c . V_g^T (sum of taps), rank + 1 values per group and channel of the
/// row. Over whichever is fewer: the elements the groups' taps touch (their
/// columns, kept across frames, then weighted sums of them) or the groups
/// (their taps summed in V_g's space first, then projected). The choice
/// depends on this frame's lights only, never on what was kept.
std::vector<float> groupTransport(LocalLightColumns& columns, const PackedModel& m, int cluster,
                                  int rank, const ClusterLights& c,
                                  const std::vector<int>& seenIndex) {
  const TransportHeader& h = m.geometry;
  const int n = m.globalBases, channels = h.channels, l = h.latticeSize(), stride = rank + 1;
  const int full = m.ranks[cluster];  // a column holds every basis, then the mean term
  const size_t groupRows = c.groupTaps.size() * channels;
  std::vector<float> towards(groupRows * stride);
  std::vector<double> sum(stride);
  if (groupRows <= c.elements.size()) {
    std::vector<float> z(n), column(full + 1);
    for (size_t gi = 0; gi < c.groupTaps.size(); ++gi)
      for (int ch = 0; ch < channels; ++ch) {
        std::fill(z.begin(), z.end(), 0.0f);
        for (const LightTap& t : c.groupTaps[gi])
          if (const int slot = seenIndex[elementOf(ch, t.texel, channels, l)]; slot >= 0) {
            const float* g = columns.globalRow(slot);
            for (int i = 0; i < n; ++i) z[i] += float(t.weight) * g[i];
          }
        columns.project(cluster, z.data(), column.data());
        float* v = towards.data() + (gi * channels + ch) * stride;
        std::copy_n(column.begin(), rank, v);
        v[rank] = column[full];
      }
    return towards;
  }
  std::vector<int> slots;
  for (int e : c.elements) slots.push_back(seenIndex[e]);
  columns.require(cluster, slots);
  for (size_t gi = 0; gi < c.groupTaps.size(); ++gi)
    for (int ch = 0; ch < channels; ++ch) {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (const LightTap& t : c.groupTaps[gi]) {
        const int slot = seenIndex[elementOf(ch, t.texel, channels, l)];
        if (slot < 0) continue;  // a direction no pixel sees: zero in V_g
        const float* column = columns.column(cluster, slot);
        for (int k = 0; k < rank; ++k) sum[k] += t.weight * column[k];
        sum[rank] += t.weight * column[full];
      }
      std::copy(sum.begin(), sum.end(), towards.begin() + (gi * channels + ch) * stride);
    }
  return towards;
}

/// The i8 step of each basis folded into the groups' transport, as the
/// environment relight folds it into the cluster's lighting (1 otherwise).
void foldSteps(const PackedModel& m, int cluster, int rank, std::vector<float>& towards) {
  const float* scale = m.scale.data() + m.lightingOffset[cluster];
  for (size_t at = 0; at < towards.size(); at += rank + 1)
    for (int k = 0; k < rank; ++k) towards[at + k] *= scale[k];
}

/// Step 3 for one chunk of 16 rows of a cluster (those of `lanes` at
/// `first`..): per light, channel and group the chunk's rows fall in (one or
/// a few: a chunk is 16 neighbouring rows), the coefficients of all 16 lanes
/// against the group's transport, read as stored (eq. 17 for one vector);
/// each row keeps its own lane, times the irradiance at its own position,
/// summed over the lights.
template <typename T>
void shadeChunk(const PackedModel& m, const T* coefficients, const std::vector<LocalLight>& lights,
                const ClusterLights& c, const std::vector<float>& towards, int rank, size_t first,
                size_t count, std::vector<float>& out) {
  const TransportHeader& h = m.geometry;
  const int channels = h.channels, stride = rank + 1;
  std::array<Rgb, kChunkRows> value;
  value.fill(Rgb::Zero());
  std::array<int, kChunkRows> lane{};
  for (size_t i = 0; i < count; ++i) lane[i] = static_cast<int>(c.lane[first + i] % kChunkRows);
  std::array<const float*, kChunkRows> group{};
  std::array<double, kChunkRows> irradiance{};
  alignas(64) float shaded[kChunkRows];
  for (size_t li = 0; li < lights.size(); ++li) {
    for (size_t i = 0; i < count; ++i)
      irradiance[i] = lightIrradiance(lights[li], positionOf(h, c.rows[first + i]));
    for (int ch = 0; ch < channels; ++ch) {
      for (size_t i = 0; i < count; ++i) {
        const size_t gi = c.groupOf[li * c.rows.size() + first + i];
        group[i] = towards.data() + (gi * channels + ch) * stride;
      }
      for (size_t i = 0; i < count; ++i) {
        if (std::find(group.begin(), group.begin() + i, group[i]) != group.begin() + i) continue;
        const float* t = group[i];
        kernels::shadeChunkOne(coefficients, t, rank, t[rank], shaded);
        for (size_t r = i; r < count; ++r) {
          // Outside a spot's cone: nothing (enclosed rows were refused before).
          if (group[r] != t || irradiance[r] <= 0) continue;
          const double transport = shaded[lane[r]];
          if (channels == 1)
            value[r] += irradiance[r] * transport * lights[li].emission;
          else
            value[r][ch] += irradiance[r] * transport * lights[li].emission[ch];
        }
      }
    }
  }
  for (size_t i = 0; i < count; ++i) {
    const size_t row = static_cast<size_t>(c.rows[first + i]);
    for (int ch = 0; ch < 3; ++ch)
      out[3 * row + ch] = static_cast<float>(h.albedo[3 * row + ch] * value[i][ch]);
  }
}

/// Step 3 for one cluster's chunks, their coefficients as stored.
template <typename T>
void shadeCluster(const PackedModel& m, const T* coefficients,
                  const std::vector<LocalLight>& lights, const ClusterLights& c,
                  const std::vector<float>& towards, int rank, std::vector<float>& out) {
  for (size_t first = 0; first < c.rows.size();) {
    const size_t chunk = c.lane[first] / kChunkRows;
    size_t count = 1;
    while (first + count < c.rows.size() && c.lane[first + count] / kChunkRows == chunk) ++count;
    shadeChunk(m, coefficients + m.chunks[chunk].coefficientOffset, lights, c, towards, rank, first,
               count, out);
    first += count;
  }
}

}  // namespace

void requireLocalLightsApply(const TransportHeader& header, const std::string& path, bool model,
                             const std::vector<LocalLight>& lights) {
  if (lights.empty()) return;
  if (header.isLightSet())
    throw UserError(concat(path,
                           ": is a captured light set: local lights need each pixel's "
                           "position, which captured images do not hold"));
  if (!header.hasPositions())
    throw UserError(
        concat(path,
               ": has no pixel positions, which local lights need (it was written before they were "
               "stored); ",
               model ? "precompute its transport again and compress (or build) it again"
                     : "precompute it again"));
  for (const LocalLight& light : lights) {
    long long inside = 0, first = -1;
    const double reach = std::visit([](const auto& kind) { return kind.reach(); }, light.shape);
    for (long long row = 0; row < header.rows(); ++row) {
      const Vec3 d = light.position - positionOf(header, row);
      if (d.squaredNorm() <= reach * reach) {
        if (inside++ == 0) first = row;
      }
    }
    if (inside > 0)
      throw ParameterError(
          "light", light.spec,
          concat(reach > 0 ? "encloses " : "sits on ", inside, " pixel position(s) of ", path,
                 ", the first at pixel ", pixelName(header, first),
                 ": a local light must lie off the surfaces it lights; move it",
                 reach > 0 ? " or make it smaller" : ""));
  }
}

std::vector<float> denseLocalRelight(const TransportReader& transport,
                                     const std::vector<LocalLight>& lights) {
  const TransportHeader& h = transport.header();
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
                                     const std::vector<LocalLight>& lights, double anchorSpread,
                                     LocalLightColumns* kept) {
  const PackedModel& m = *relighter.packed();
  const TransportHeader& h = m.geometry;
  const CubeLattice lattice(h.cubemapResolution);
  std::vector<float> out(3 * static_cast<size_t>(m.rows()), 0.0f);
  if (lights.empty() || m.rows() == 0) return out;
  std::unique_ptr<LocalLightColumns> own;
  if (!kept) own = std::make_unique<LocalLightColumns>(relighter.packed());
  LocalLightColumns& columns = kept ? *kept : *own;
  ACPCA_CHECK(columns.model() == relighter.packed(), "local-light columns of another model");
  if (columns.keptValues() > LocalLightColumns::kMaxKeptValues) columns.clear();
  const std::vector<int>& seenIndex = columns.seenIndex();

  // 1. Per cluster and light, its rows in groups, each group's direction taps
  //    at its anchor, and the elements the cluster needs.
  std::vector<ClusterLights> clusters(m.clusters());
  for (int cluster = 0; cluster < m.clusters(); ++cluster) {
    clusters[cluster].rows = columns.rowsOf(cluster);
    clusters[cluster].lane = columns.lanesOf(cluster);
  }
  tbb::parallel_for(0, m.clusters(), [&](int cluster) {
    findGroupTaps(h, lattice, lights, seenIndex, anchorSpread, clusters[cluster]);
  });

  // V_g's rows for every element some cluster needs.
  std::vector<int> slots;
  for (const ClusterLights& c : clusters)
    for (int e : c.elements) slots.push_back(seenIndex[e]);
  std::sort(slots.begin(), slots.end());
  slots.erase(std::unique(slots.begin(), slots.end()), slots.end());
  columns.requireGlobalRows(slots);

  // 2. and 3. Per cluster each group's transport towards its light, then
  //    its rows chunk by chunk.
  tbb::parallel_for(0, m.clusters(), [&](int cluster) {
    const ClusterLights& c = clusters[cluster];
    const int rank = relighter.activeRanks()[cluster];
    if (c.elements.empty() || (rank == 0 && !m.hasMean)) return;
    std::vector<float> towards = groupTransport(columns, m, cluster, rank, c, seenIndex);
    foldSteps(m, cluster, rank, towards);
    switch (m.precision) {
      case CoeffPrecision::F32:
        return shadeCluster(m, m.coeffF32.data(), lights, c, towards, rank, out);
      case CoeffPrecision::F16:
        return shadeCluster(m, m.coeffF16.data(), lights, c, towards, rank, out);
      case CoeffPrecision::I8:
        return shadeCluster(m, m.coeffI8.data(), lights, c, towards, rank, out);
    }
  });
  return out;
}

}  // namespace acpca
