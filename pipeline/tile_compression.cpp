#include "pipeline/tile_compression.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "cluster/compress.h"
#include "cluster/model_fit.h"
#include "cluster/partition.h"
#include "core/error.h"
#include "core/text.h"
#include "model/model_reference.h"

namespace acpca {

bool clustersTileGroups(Method m) {
  return m == Method::Cpca || m == Method::AdaptiveBinary;
}

int tileSide(const BuildOptions& o) {
  const CompressOptions& c = o.compress;
  if (clustersTileGroups(c.method)) return o.tileSide > 0 ? o.tileSide : 256;
  const int block = blockSideFor(c);
  return c.method == Method::AdaptiveQuad ? block : block * std::max(1, 64 / block);
}

Model compressTile(const Tile& tile, const RowSource& source, const BasisProjector& projector,
                   const GlobalBasis& basis, const BuildOptions& o, const GroundTruth& truthSet,
                   std::vector<float>& rows, std::vector<float>& truth, TileEnergies& energies,
                   std::pair<long long, long long>& rays) {
  const TransportHeader& header = source.header();
  const long long count = static_cast<long long>(tile.rows.size());
  const int l = source.rowLength();
  // `rows` is the slot's, reused tile after tile: a fresh 100 MB buffer per
  // tile cost more in page faults than the tile's projection.
  rows.resize(static_cast<size_t>(count) * l);
  rays = source.render(tile.rows, rows.data());
  const GlobalProjection projection = projector.project(rows.data(), count);

  // The tile's own geometry: its rows' albedo, numbered from 0.
  TransportHeader local;
  local.cubemapResolution = header.cubemapResolution;
  local.channels = header.channels;
  local.pixels.resize(static_cast<size_t>(count));
  for (long long i = 0; i < count; ++i) {
    local.pixels[i] = static_cast<std::int32_t>(i);
    for (int c = 0; c < 3; ++c) local.albedo.push_back(header.albedo[3 * tile.rows[i] + c]);
  }
  const int maps = truthSet.maps();
  truth.assign(static_cast<size_t>(maps) * count * 3, 0.0f);
  if (maps > 0) {  // B = albedo (T L), as denseRelight computes it from a file
    const Eigen::MatrixXf product =
        Eigen::Map<const RowMatrixF>(rows.data(), count, l) * truthSet.onRows;
    for (int m = 0; m < maps; ++m)
      for (long long i = 0; i < count; ++i)
        for (int c = 0; c < 3; ++c)
          truth[(static_cast<size_t>(m) * count + i) * 3 + c] =
              local.albedo[3 * i + c] * product(i, 3 * m + c);
  }

  const std::vector<std::int32_t> pixels = tilePixels(tile, header.camera.size, header.pixels);
  const CompressOptions& c = o.compress;
  const bool mean = keepsMean(c.method);
  const ClusterInput in{
      &projection.coefficients, &pixels, {tile.width, tile.height}, c.tolerance, mean,
      c.clusteringDims};
  CompressOptions here = c;      // the tile alone: the tile is the root block
  if (c.method == Method::Cpca)  // K clusters over the image: each group its share by rows
    here.clusters = static_cast<int>(std::clamp<long long>(
        std::llround(double(c.clusters) * count / std::max(1LL, header.rows())), 1, count));
  if (c.method == Method::AdaptiveBinary)  // the initial clusters in every group
    here.clusters = static_cast<int>(std::min<long long>(c.clusters, count));
  const Partition partition = partitionRows(in, here);
  ModelOptions m;
  m.tolerance = c.tolerance;
  m.mean = mean;
  m.precision = c.coeffs;
  m.basisPrecision = c.bases;
  Model part = buildModel(local, basis, projection, partition, m);
  energies.energy = projection.transportEnergy();
  energies.globalResidual = projection.residualEnergy.sum();
  energies.errorEnergy = part.transportError * part.transportError * energies.energy;
  if (maps > 0) {  // the model's image error, as eval measures it (relative L2 over RGB)
    const auto relit = relightModelReference(part, truthSet.lightings);
    energies.truthDiff.assign(maps, 0.0), energies.truthNorm.assign(maps, 0.0);
    for (int map = 0; map < maps; ++map)
      for (long long k = 0; k < 3 * count; ++k) {
        const double t = truth[static_cast<size_t>(map) * count * 3 + k];
        energies.truthDiff[map] += (relit[map][k] - t) * (relit[map][k] - t);
        energies.truthNorm[map] += t * t;
      }
  }
  part.globalBasis.resize(0, 0);
  part.geometry = TransportHeader();
  for (auto& r : part.clusterRows) r = static_cast<std::int32_t>(tile.rows[r]);
  return part;
}

}  // namespace acpca
