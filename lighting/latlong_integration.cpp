#include "lighting/latlong_integration.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <tuple>

#include "core/error.h"
#include "lighting/builtin_maps.h"

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;

/// acc[3 j + c] += omega * p[c] for each cell of a row in turn (j its texel, p
/// its map pixel). Neighbouring cells mostly share a texel: its sums stay in
/// registers over the run, the same additions in the same order.
void addRow(const float* pixels, int sub, int cells, const int* texel, double omega,
            std::vector<double>& acc) {
  int current = -1;
  double sum[3] = {0, 0, 0};
  for (int i = 0; i < cells; ++i) {
    const float* p = pixels + 3 * (i / sub);
    if (p[0] == 0 && p[1] == 0 && p[2] == 0) continue;
    if (texel[i] != current) {
      if (current >= 0)
        for (int c = 0; c < 3; ++c) acc[3 * current + c] = sum[c];
      current = texel[i];
      for (int c = 0; c < 3; ++c) sum[c] = acc[3 * current + c];
    }
    for (int c = 0; c < 3; ++c) sum[c] += omega * p[c];
  }
  if (current >= 0)
    for (int c = 0; c < 3; ++c) acc[3 * current + c] = sum[c];
}

/// Sub-row r's polar angle at its centre, and its solid angle per sub-cell.
struct SubRow {
  double sinT, cosT, omega;
};
SubRow subRow(int r, int subH, int subW) {
  const double theta0 = kPi * r / subH, theta1 = kPi * (r + 1) / subH;
  const double theta = 0.5 * (theta0 + theta1);
  return {std::sin(theta), std::cos(theta),
          (std::cos(theta0) - std::cos(theta1)) * (2 * kPi / subW)};
}

/// Sub-cell i's azimuth: u = 0.5 + phi / 2 pi at the cell's centre.
double cellAzimuth(long long i, int subW) {
  return 2 * kPi * ((i + 0.5) / subW - 0.5);
}

/// Where each sub-row's circle of latitude crosses the lattice: arcs
/// [start_k, start_k+1) (azimuths in [0, 2 pi), the last wrapping to the
/// first) and the texel each lies in.
struct RowArcs {
  std::vector<std::vector<int>> texel;
  /// Each arc's start in sub-cell units, (start + pi) x cells per radian -
  /// 1/2: under a turn t the arc's first sub-cell is ceil(that - t x cells
  /// per radian).
  std::vector<std::vector<double>> firstCell;
};

/// The azimuths in [0, 2 pi) where the circle (rho sin a, y, -rho cos a)
/// meets the plane n . d = 0.
void planeCrossings(const Vec3& n, double rho, double y, std::vector<double>& out) {
  // n.x rho sin a - n.z rho cos a + n.y y = 0, as R sin(a + delta) = -C.
  const double a = n.x() * rho, b = -n.z() * rho, c = n.y() * y;
  const double r = std::hypot(a, b);
  if (!(r > 0) || std::abs(c) > r) return;
  const double delta = std::atan2(b, a), s = std::asin(std::clamp(-c / r, -1.0, 1.0));
  for (double root : {s - delta, kPi - s - delta}) {
    root = std::fmod(root, 2 * kPi);
    out.push_back(root < 0 ? root + 2 * kPi : root);
  }
}

RowArcs rowArcsOf(const CubeLattice& lattice, int subW, int subH) {
  // Texels and faces are bounded by planes a = k b through the origin (a, b
  // two axes; k on the texel grid of [-1, 1], k = +-1 the faces' edges).
  const int n = lattice.resolution();
  std::vector<Vec3> planes;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (a != b)
        for (int m = 0; m <= n; ++m) {
          Vec3 normal = Vec3::Zero();
          normal[a] = 1;
          normal[b] = -(-1 + 2.0 * m / n);
          planes.push_back(normal);
        }
  RowArcs arcs;
  arcs.texel.resize(subH);
  arcs.firstCell.resize(subH);
  tbb::parallel_for(0, subH, [&](int r) {
    const SubRow row = subRow(r, subH, subW);
    std::vector<double> cuts{0.0};
    for (const Vec3& plane : planes) planeCrossings(plane, row.sinT, row.cosT, cuts);
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    // Each arc's texel at its middle, classified as the cells are.
    const size_t k = cuts.size();
    std::vector<double> x(k), y(k, row.cosT), z(k);
    for (size_t i = 0; i < k; ++i) {
      const double end = i + 1 < k ? cuts[i + 1] : 2 * kPi;
      const double middle = 0.5 * (cuts[i] + end);
      x[i] = row.sinT * std::sin(middle), z[i] = -row.sinT * std::cos(middle);
    }
    std::vector<int> texel(k);
    lattice.texelsOf(x.data(), y.data(), z.data(), static_cast<int>(k), texel.data());
    for (size_t i = 0; i < k; ++i)
      if (i == 0 || texel[i] != arcs.texel[r].back()) {
        arcs.texel[r].push_back(texel[i]);
        arcs.firstCell[r].push_back((cuts[i] + kPi) * (subW / (2 * kPi)) - 0.5);
      }
  });
  return arcs;
}

/// The arcs of a lattice and sub-cell grid, made once per process and shared
/// by every map of that size.
std::shared_ptr<const RowArcs> rowArcs(const CubeLattice& lattice, int subW, int subH) {
  static std::mutex mutex;
  static std::map<std::tuple<int, int, int>, std::shared_ptr<const RowArcs>> made;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& arcs = made[{lattice.resolution(), subW, subH}];
  // Isolated: while this thread waits on the rows it runs none of a
  // caller's other tasks, which could come back to this lock.
  if (!arcs)
    tbb::this_task_arena::isolate(
        [&] { arcs = std::make_shared<const RowArcs>(rowArcsOf(lattice, subW, subH)); });
  return arcs;
}

}  // namespace

int latLongSubCells(const LatLongPixels& map, const CubeLattice& lattice) {
  const double texelAngle = 0.5 * kPi / lattice.resolution();
  return std::max(
      1, static_cast<int>(std::ceil(kMapSubCellsPerTexel * (kPi / map.height) / texelAngle)));
}

bool isYawOnly(const Eigen::Matrix3d& rotation) {
  return rotation(1, 1) == 1 && rotation(0, 1) == 0 && rotation(1, 0) == 0 && rotation(1, 2) == 0 &&
         rotation(2, 1) == 0;
}

void integrateLatLongCells(const LatLongPixels& map, const CubeLattice& lattice,
                           const Eigen::Matrix3d& rotation, LatticeLighting& lighting) {
  ACPCA_CHECK(lighting.size() == 3u * lattice.size(), "lighting size ", lighting.size());
  const int sub = latLongSubCells(map, lattice);
  const int subW = map.width * sub, subH = map.height * sub;
  std::vector<double> sinPhi(subW), cosPhi(subW);
  for (int i = 0; i < subW; ++i) {
    const double phi = cellAzimuth(i, subW);
    sinPhi[i] = std::sin(phi), cosPhi[i] = std::cos(phi);
  }
  // Fixed chunks of source rows, each with its own partial sums, added in
  // order: the result does not depend on the thread count.
  constexpr int kChunks = 16;
  const int chunkRows = (subH + kChunks - 1) / kChunks;
  const int chunks = (subH + chunkRows - 1) / chunkRows;
  std::vector<std::vector<double>> partial(chunks);
  tbb::parallel_for(0, chunks, [&](int chunk) {
    auto& acc = partial[chunk];
    acc.assign(lighting.size(), 0.0);
    std::vector<double> x(subW), y(subW), z(subW);
    std::vector<int> texel(subW);
    for (int r = chunk * chunkRows; r < std::min(subH, (chunk + 1) * chunkRows); ++r) {
      const SubRow row = subRow(r, subH, subW);
      // The row's cells under the rotation, then their texels in SIMD lanes.
      for (int i = 0; i < subW; ++i) {
        const Vec3 d = rotation * Vec3(row.sinT * sinPhi[i], row.cosT, -row.sinT * cosPhi[i]);
        x[i] = d.x(), y[i] = d.y(), z[i] = d.z();
      }
      lattice.texelsOf(x.data(), y.data(), z.data(), subW, texel.data());
      addRow(map.rgb + 3 * static_cast<size_t>(r / sub) * map.width, sub, subW, texel.data(),
             row.omega, acc);
    }
  });
  for (const auto& acc : partial)
    for (size_t k = 0; k < lighting.size(); ++k) lighting[k] += acc[k];
}

LatLongRowSums::LatLongRowSums(const LatLongPixels& map)
    : width_(map.width),
      entries_(map.width / kBlock + 2),
      rgb_(map.rgb),
      sums_(static_cast<size_t>(map.height) * entries_ * 3) {
  tbb::parallel_for(0, map.height, [&](int row) {
    double* s = &sums_[static_cast<size_t>(row) * entries_ * 3];
    const float* p = rgb_ + static_cast<size_t>(row) * width_ * 3;
    double sum[3] = {0, 0, 0};
    for (int x = 0; x < width_; ++x) {
      if (x % kBlock == 0)
        for (int c = 0; c < 3; ++c) s[3 * (x / kBlock) + c] = sum[c];
      for (int c = 0; c < 3; ++c) sum[c] += p[3 * x + c];
    }
    for (int c = 0; c < 3; ++c) s[3 * (entries_ - 1) + c] = sum[c];
  });
}

void LatLongRowSums::upTo(int row, long long i, int sub, double out[3]) const {
  // Whole turns of the row first (i may lie outside [0, width x sub)).
  const long long cells = static_cast<long long>(width_) * sub;
  long long laps = 0;
  if (i < 0 || i >= cells)
    laps = i >= 0 ? i / cells : -((-i + cells - 1) / cells), i -= laps * cells;
  const long long pixel = sub == 1 ? i : i / sub, part = sub == 1 ? 0 : i % sub;
  const double* rowSums = &sums_[static_cast<size_t>(row) * entries_ * 3];
  const double* total = rowSums + 3 * (entries_ - 1);
  const long long block = pixel / kBlock;
  const float* p = rgb_ + static_cast<size_t>(row) * width_ * 3;
  // The pixels from the block's start, added in the order the sum ran.
  double before[3] = {rowSums[3 * block], rowSums[3 * block + 1], rowSums[3 * block + 2]};
  for (long long x = block * kBlock; x < pixel; ++x)
    for (int c = 0; c < 3; ++c) before[c] += p[3 * x + c];
  for (int c = 0; c < 3; ++c)
    out[c] = sub * (laps * total[c] + before[c]) +
             (part ? part * static_cast<double>(p[3 * pixel + c]) : 0.0);
}

namespace {

/// Row r's arcs under a turn of `turnCells` sub-cells, added onto `acc`.
void addRowArcs(const LatLongRowSums& sums, const RowArcs& arcs, int r, int sub, int subW,
                double omega, double turnCells, double* acc) {
  const int pixelRow = r / sub;
  const std::vector<double>& firstCell = arcs.firstCell[r];
  const std::vector<int>& texel = arcs.texel[r];
  // Cell i lies in arc k when start_k <= azimuth_i + turn < start_k+1.
  const auto cellOf = [&](size_t k) {
    return static_cast<long long>(std::ceil(firstCell[k] - turnCells));
  };
  const long long first = cellOf(0);
  long long begin = first;
  double below[3], upToEnd[3];
  sums.upTo(pixelRow, begin, sub, below);
  // The sums an arc reads are a cache miss apart: fetched a few arcs ahead.
  constexpr size_t kAhead = 6;
  const long long cells = subW;
  const auto prefetch = [&](size_t k) {
    long long i = cellOf(k) % cells;
    sums.prefetch(pixelRow, i < 0 ? i + cells : i, sub);
  };
  for (size_t k = 1; k < std::min(texel.size(), kAhead); ++k) prefetch(k);
  for (size_t k = 0; k < texel.size(); ++k) {
    if (k + kAhead < texel.size()) prefetch(k + kAhead);
    const long long end = k + 1 < texel.size() ? cellOf(k + 1) : first + subW;
    if (end <= begin) continue;
    sums.upTo(pixelRow, end, sub, upToEnd);
    double* out = &acc[3 * static_cast<size_t>(texel[k])];
    for (int c = 0; c < 3; ++c) {
      out[c] += omega * (upToEnd[c] - below[c]);
      below[c] = upToEnd[c];
    }
    begin = end;
  }
}

}  // namespace

void integrateLatLongYawed(const LatLongPixels& map, const LatLongRowSums& sums,
                           const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                           LatticeLighting& lighting) {
  std::vector<LatticeLighting*> one{&lighting};
  integrateLatLongYaws(map, sums, lattice, {rotation}, one);
}

void integrateLatLongYaws(const LatLongPixels& map, const LatLongRowSums& sums,
                          const CubeLattice& lattice, const std::vector<Eigen::Matrix3d>& rotations,
                          const std::vector<LatticeLighting*>& lightings) {
  ACPCA_CHECK(rotations.size() == lightings.size(), rotations.size(), " rotations, ",
              lightings.size(), " lightings");
  const size_t frames = rotations.size();
  const size_t values = 3u * lattice.size();
  for (size_t f = 0; f < frames; ++f) {
    ACPCA_CHECK(lightings[f]->size() == values, "lighting size ", lightings[f]->size());
    ACPCA_CHECK(isYawOnly(rotations[f]), "not a yaw: ", rotations[f]);
  }
  const int sub = latLongSubCells(map, lattice);
  const int subW = map.width * sub, subH = map.height * sub;
  const std::shared_ptr<const RowArcs> arcs = rowArcs(lattice, subW, subH);
  // R turns every azimuth by the same angle: that of R (0, 0, -1).
  std::vector<double> turnCells(frames);
  for (size_t f = 0; f < frames; ++f)
    turnCells[f] = std::atan2(-rotations[f](0, 2), rotations[f](2, 2)) * (subW / (2 * kPi));
  // Each frame: fixed chunks of rows, each with its own sums, added in
  // order: the same result for any thread count or set of frames. A task
  // takes a chunk's rows for up to kFramesATask frames, each row for all
  // of them in turn while its pixels and sums are in cache.
  constexpr int kChunks = 4;
  constexpr size_t kFramesATask = 8;
  const int chunkRows = (subH + kChunks - 1) / kChunks;
  const size_t frameSets = (frames + kFramesATask - 1) / kFramesATask;
  std::vector<LatticeLighting> partial(frames * kChunks);
  tbb::parallel_for(size_t(0), kChunks * frameSets, [&](size_t task) {
    const int chunk = static_cast<int>(task % kChunks);
    const size_t f0 = task / kChunks * kFramesATask, f1 = std::min(frames, f0 + kFramesATask);
    for (size_t f = f0; f < f1; ++f) partial[f * kChunks + chunk].assign(values, 0.0);
    for (int r = chunk * chunkRows; r < std::min(subH, (chunk + 1) * chunkRows); ++r) {
      const double omega = subRow(r, subH, subW).omega;
      for (size_t f = f0; f < f1; ++f)
        addRowArcs(sums, *arcs, r, sub, subW, omega, turnCells[f],
                   partial[f * kChunks + chunk].data());
    }
  });
  for (size_t f = 0; f < frames; ++f)
    for (int chunk = 0; chunk < kChunks; ++chunk) {
      const LatticeLighting& acc = partial[f * kChunks + chunk];
      LatticeLighting& lighting = *lightings[f];
      for (size_t k = 0; k < values; ++k) lighting[k] += acc[k];
    }
}

}  // namespace acpca
