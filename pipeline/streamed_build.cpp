#include "pipeline/streamed_build.h"

#include <tbb/parallel_for.h>

#include <unistd.h>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <numeric>

#include "cluster/global_basis.h"
#include "cluster/model_file.h"
#include "cluster/model_fit.h"
#include "cluster/model_reference.h"
#include "cluster/partition.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/ordered_pipeline.h"
#include "core/ranks.h"
#include "core/stopwatch.h"
#include "pipeline/tile_plan.h"
#include "precompute/transport/hdf5_handles.h"
#include "precompute/transport/row_layout.h"
#include "relight/environment.h"
#include "relight/image_output.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// The energies a tile's transport error is assembled from: |T|^2, what the
/// global basis misses, and everything the tile's model misses (the global
/// residual, its clusters' residuals and the quantization error).
struct TileEnergies {
  double energy = 0, globalResidual = 0, errorEnergy = 0;
  /// Per ground-truth lighting: sum over the tile's rows of |B_model - B|^2 and |B|^2.
  std::vector<double> truthDiff, truthNorm;
  std::map<std::string, double> attributes() const {
    std::map<std::string, double> a{
        {"energy", energy}, {"global_residual", globalResidual}, {"error_energy", errorEnergy}};
    for (size_t m = 0; m < truthDiff.size(); ++m)
      a[concat("truth_diff_", m)] = truthDiff[m], a[concat("truth_norm_", m)] = truthNorm[m];
    return a;
  }
};

/// The lightings of the ground truth, integrated onto the lattice once.
struct GroundTruth {
  std::vector<std::unique_ptr<Environment>> environments;
  std::vector<std::vector<double>> lightings;
  Eigen::MatrixXf onRows;  ///< rowLength x 3M: column 3m + c is map m's channel c on the rows
  int maps() const { return static_cast<int>(environments.size()); }
};

/// The environments, before any work (a bad spec is refused first).
GroundTruth loadGroundTruth(const BuildOptions& o) {
  GroundTruth g;
  for (const auto& spec : o.groundTruth) g.environments.push_back(loadEnvironment(spec));
  return g;
}

/// Integrated onto the lattice and laid out as the rows meet them.
void layOutGroundTruth(GroundTruth& g, int cubemapResolution, int channels) {
  const CubeLattice lattice(cubemapResolution);
  for (const auto& env : g.environments) {
    std::vector<double> lighting(3 * static_cast<size_t>(lattice.size()), 0.0);
    env->integrate(lattice, Eigen::Matrix3d::Identity(), lighting);
    g.lightings.push_back(std::move(lighting));
  }
  g.onRows.resize(static_cast<Eigen::Index>(channels) * lattice.size(), 3 * g.maps());
  for (int m = 0; m < g.maps(); ++m)
    g.onRows.middleCols(3 * m, 3) = lightingOnRows<float>(g.lightings[m], lattice.size(), channels);
}

/// FNV-1a over bytes: a fingerprint of what a resumed build must share with
/// the build it continues (not a defence against tampering).
std::uint64_t fingerprint(const void* data, size_t bytes,
                          std::uint64_t hash = 14695981039346656037ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 1099511628211ull;
  return hash;
}

void validate(const BuildOptions& o) {
  validateCompressOptions(o.compress);
  if (o.compress.method == Method::Global)
    throw ParameterError("method", "global",
                         "is one cluster of every row, which a streamed build never holds; run "
                         "precompute, then compress");
  if (o.compress.allocateRanks)
    throw ParameterError("allocate ranks", "on",
                         "needs every cluster's spectrum at once, which a streamed build never "
                         "holds; run precompute, then compress");
  if (o.tileSide < 0) throw ParameterError("tile side", o.tileSide, "must be >= 1 (0: default)");
  if (o.tilesInFlight < 1) throw ParameterError("tiles in flight", o.tilesInFlight, "must be >= 1");
  if (!o.groundTruthDir.empty() && o.groundTruth.empty())
    throw ParameterError("ground-truth lightings", "none", "are needed for ground-truth images");
}

/// CPCA and adaptive binary cluster rows wherever they are, so their tiles
/// are groups of pixels large enough to hold many clusters.
bool clustersTileGroups(Method m) {
  return m == Method::Cpca || m == Method::AdaptiveBinary;
}

/// Tile side: adaptive-quad's root block; for block, whole blocks of about 64;
/// for CPCA and adaptive binary, groups of 256 unless told.
int tileSide(const BuildOptions& o) {
  const CompressOptions& c = o.compress;
  if (clustersTileGroups(c.method)) return o.tileSide > 0 ? o.tileSide : 256;
  const int block = blockSideFor(c);
  return c.method == Method::AdaptiveQuad ? block : block * std::max(1, 64 / block);
}

std::string tilePath(const std::string& dir, size_t tile) {
  char name[32];
  std::snprintf(name, sizeof name, "tile-%07zu.h5", tile);
  return (fs::path(dir) / name).string();
}

/// The model's settings, as compress records them, plus how its rows were made.
std::string settingsJson(const BuildOptions& o, const Scene& scene, int tile) {
  const CompressOptions& c = o.compress;
  const PrecomputeOptions& r = o.render;
  return nlohmann::json{{"method", methodName(c.method)},
                        {"tolerance", c.tolerance},
                        {"global_energy", c.globalEnergy},
                        {"block", blockSideFor(c)},
                        {"exact_quad_tree", c.exactQuadTree},
                        {"coeffs", coeffPrecisionName(c.coeffs)},
                        {"bases", coeffPrecisionName(c.bases)},
                        {"sample_rows", c.sampleRows},
                        {"seed", c.seed},
                        {"mean", clustersTileGroups(c.method)},
                        {"clusters", c.clusters},
                        {"clustering_dims", c.clusteringDims},
                        {"source", concat("build of ", scene.name)},
                        {"streamed", true},
                        {"tile", tile},
                        {"cubemap", r.cubemapResolution},
                        {"spp", r.samplesPerPixel},
                        {"antialiasing", kAntialiasingNames.name(r.antialiasing)},
                        {"texel_rays", r.texelRays},
                        {"precision", precisionName(r.precision)},
                        {"bounces", r.bounces},
                        {"indirect_samples", r.indirectSamples},
                        {"indirect_cache_cell", r.indirectCacheCell}}
      .dump();
}

/// Renders the sampled rows and fits the global basis to them, as
/// computeGlobalBasis does from a transport file (same rows, same values).
GlobalBasis fitBasis(const RowSource& source, const GlobalBasisOptions& options,
                     BuildStats& stats) {
  const BasisSample sample = chooseBasisSample(source.header().rows(), options);
  const int l = source.rowLength();
  const auto renderRows = [&](const std::vector<long long>& rows) {
    std::vector<float> values(rows.size() * static_cast<size_t>(l));
    const auto [shadow, paths] = source.render(rows, values.data());
    stats.occlusionRays += shadow, stats.pathRays += paths;
    return Eigen::Map<const RowMatrixF>(values.data(), static_cast<Eigen::Index>(rows.size()), l)
        .cast<double>()
        .eval();
  };
  const Eigen::MatrixXd held = renderRows(sample.heldOut);
  const Eigen::MatrixXd rows = renderRows(sample.rows);
  return basisFromSample(rows, held, options);
}

/// Values appended to / read from a byte message in order.
struct Bytes {
  std::vector<char> data;
  size_t at = 0;
  template <typename T>
  void put(const T* values, size_t count) {
    const auto* p = reinterpret_cast<const char*>(values);
    data.insert(data.end(), p, p + count * sizeof(T));
  }
  template <typename T>
  void get(T* values, size_t count) {
    ACPCA_CHECK(at + count * sizeof(T) <= data.size(), "message shorter than its contents");
    std::memcpy(values, data.data() + at, count * sizeof(T));
    at += count * sizeof(T);
  }
};

/// Rank 0's basis on every rank: it alone renders the sample and fits the
/// basis, so every rank projects with the same values.
void shareBasis(GlobalBasis& basis) {
  Bytes b;
  if (ranks::rank() == 0) {
    const long long sizes[4] = {basis.basis.rows(), basis.basis.cols(),
                                static_cast<long long>(basis.active.size()),
                                (static_cast<long long>(basis.activeDirections) << 32) |
                                    static_cast<unsigned>(basis.sampledRows)};
    const double kept[2] = {basis.sampleEnergyKept, basis.heldOutEnergyKept};
    b.put(sizes, 4), b.put(kept, 2), b.put(basis.active.data(), basis.active.size());
    b.put(basis.basis.data(), static_cast<size_t>(basis.basis.size()));
  }
  ranks::broadcast(b.data);
  if (ranks::rank() == 0) return;
  long long sizes[4];
  double kept[2];
  b.get(sizes, 4), b.get(kept, 2);
  basis.active.resize(static_cast<size_t>(sizes[2]));
  b.get(basis.active.data(), basis.active.size());
  basis.basis.resize(sizes[0], sizes[1]);
  b.get(basis.basis.data(), static_cast<size_t>(basis.basis.size()));
  basis.activeDirections = static_cast<int>(sizes[3] >> 32);
  basis.sampledRows = static_cast<int>(sizes[3] & 0xffffffff);
  basis.sampleEnergyKept = kept[0], basis.heldOutEnergyKept = kept[1];
}

/// A file's bytes, and a file written from bytes atomically.
std::vector<char> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<char>& bytes) {
  AtomicOutput output(path);
  {
    std::ofstream out(output.tempPath(), std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw WriteError(concat(path, ": cannot write (disk full?)"));
  }
  output.commit();
}

/// A tile's clusters: its rows rendered, projected onto the global basis and
/// compressed with the tile as the root block; rows indexed in the image.
/// With a ground truth, its values for the tile's rows (map by map, row by
/// row, RGB) go into `truth`, and the model's error against them into energies.
Model compressTile(const Tile& tile, const RowSource& source, const BasisProjector& projector,
                   const GlobalBasis& basis, const BuildOptions& o, const GroundTruth& truthSet,
                   int side, std::vector<float>& rows, std::vector<float>& truth,
                   TileEnergies& energies, std::pair<long long, long long>& rays) {
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
  const bool mean = clustersTileGroups(c.method);  // the CPCA family keeps a mean, as compress
  const ClusterInput in{
      &projection.coefficients, &pixels, {tile.width, tile.height}, c.tolerance, mean,
      c.clusteringDims};
  Partition partition;
  CpcaOptions cpcaOptions;
  cpcaOptions.seed = c.seed;
  switch (c.method) {
    case Method::AdaptiveQuad: {
      QuadTreeOptions q;
      q.rootBlock = side;
      q.exact = c.exactQuadTree;
      partition = adaptiveQuadTree(in, q);
      break;
    }
    case Method::Block:
      partition = fixedBlocks(in, blockSideFor(c));
      break;
    case Method::Cpca: {  // K clusters over the image: each group its share by rows
      cpcaOptions.clusters = static_cast<int>(std::clamp<long long>(
          std::llround(double(c.clusters) * count / std::max(1LL, header.rows())), 1, count));
      std::vector<int> all(static_cast<size_t>(count));
      std::iota(all.begin(), all.end(), 0);
      partition = cpca(in, all, cpcaOptions);
      break;
    }
    case Method::AdaptiveBinary: {  // the initial clusters in every group
      BinaryOptions b;
      b.initialClusters = static_cast<int>(std::min<long long>(c.clusters, count));
      b.split = cpcaOptions;
      partition = adaptiveBinary(in, b);
      break;
    }
    case Method::Global:
      ACPCA_CHECK(false, "global is refused before any work");
  }
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

/// A float dataset of a tile file, of the size expected.
std::vector<float> readTileArray(const std::string& path, const std::string& name, size_t size) {
  const h5::Handle file = h5::openFileReadOnly(path);
  if (h5::datasetShape(file.get(), name, path) != std::vector<hsize_t>{size})
    throw UserError(concat(path, ": dataset '", name, "' has the wrong size"));
  std::vector<float> values(size);
  h5::readDataset(file.get(), name, values.data(), path);
  return values;
}

/// Starts the work directory over, or checks that it belongs to this build.
void prepareWorkDirectory(const std::string& dir, const std::string& identity, bool resume,
                          const std::function<void(const std::string&)>& log) {
  const std::string stamp = (fs::path(dir) / "build.json").string();
  std::error_code ec;
  if (resume && fs::exists(stamp, ec)) {
    std::ifstream in(stamp);
    const std::string found((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (found != identity)
      throw UserError(concat(dir,
                             ": was left by a build of another scene or other settings; "
                             "run without --resume to start over"));
    return;
  }
  if (fs::exists(dir, ec)) {
    if (log) log(concat("starting over: removing ", dir, resume ? "" : " (--resume continues it)"));
    fs::remove_all(dir, ec);
    if (ec) throw WriteError(concat(dir, ": cannot remove (", ec.message(), ")"));
  }
  createOutputDirectory(dir);
  writeTextFile(stamp, identity);
}

}  // namespace

std::string buildWorkDirectory(const std::string& outPath) {
  return outPath + ".tiles";
}

BuildStats buildStreamed(const Scene& scene, const std::string& outPath, const BuildOptions& o) {
  validate(o);
  const Stopwatch watch;
  const auto log = [&](const std::string& s) {
    if (o.log && ranks::rank() == 0)  // stages once; every rank names its tiles
      o.log(concat("[", std::fixed, std::setprecision(1), watch.seconds(), " s] ", s));
  };
  BuildStats stats;
  { AtomicOutput check(outPath); }  // the output's directory exists, before any work
  if (!o.groundTruthDir.empty()) createOutputDirectory(o.groundTruthDir);
  GroundTruth truthSet = loadGroundTruth(o);

  const RowSource source(scene, o.render);
  const TransportHeader& header = source.header();
  layOutGroundTruth(truthSet, header.cubemapResolution, header.channels);
  stats.rows = header.rows();
  log(concat("G-buffer: ", header.rows(), " occupied pixels"));

  const CompressOptions& c = o.compress;
  const int rank = ranks::rank(), rankCount = ranks::count();
  const bool lead = rank == 0;
  GlobalBasis basis;
  if (lead) basis = fitBasis(source, {c.globalEnergy, c.sampleRows, c.seed}, stats);
  shareBasis(basis);
  stats.globalBases = basis.globalBases();
  stats.sampleEnergyKept = basis.sampleEnergyKept;
  stats.heldOutEnergyKept = basis.heldOutEnergyKept;
  stats.basisSeconds = watch.seconds();
  log(concat("global basis: N = ", basis.globalBases(), " of ", basis.activeDirections,
             " directions the sample sees, ", basis.sampleEnergyKept, " of the sample's energy (",
             basis.heldOutEnergyKept, " on held-out rows)"));

  const int side = tileSide(o);
  const std::vector<Tile> tiles = planTiles(header.camera.size, header.pixels, side);
  stats.tiles = static_cast<long long>(tiles.size());
  Model head;
  head.geometry = header;
  head.method = methodName(c.method);
  head.settings = settingsJson(o, scene, side);
  head.globalBasis = basis.basis;
  head.hasMean = clustersTileGroups(c.method);
  head.precision = c.coeffs;
  head.basisPrecision = c.bases;

  // What a resumed build must share: settings, the image's rows and the basis.
  std::uint64_t hash = fingerprint(header.pixels.data(), header.pixels.size() * 4);
  hash = fingerprint(header.albedo.data(), header.albedo.size() * 4, hash);
  hash = fingerprint(basis.basis.data(), basis.basis.size() * 4, hash);
  const std::string dir = buildWorkDirectory(outPath);
  // Rank 0 keeps the work directory and says which tiles are left to do.
  Bytes todoMessage;
  if (lead) {
    prepareWorkDirectory(dir, head.settings + "\n" + std::to_string(hash) + "\n", o.resume, o.log);
    for (size_t t = 0; t < tiles.size(); ++t) {
      std::error_code ec;
      const char done = o.resume && fs::exists(tilePath(dir, t), ec);
      todoMessage.put(&done, 1);
    }
  }
  ranks::broadcast(todoMessage.data);
  // Tiles left to do are dealt round robin; rank 0 writes every finished tile
  // in tile order, its own and those the others send, so the files do not
  // depend on the rank count.
  std::vector<size_t> todo, mine;
  for (size_t t = 0; t < tiles.size(); ++t)
    if (!todoMessage.data[t]) todo.push_back(t);
  for (size_t i = 0; i < todo.size(); ++i)
    if (static_cast<int>(i % rankCount) == rank) mine.push_back(todo[i]);
  const auto owner = [&](size_t i) { return static_cast<int>(i % rankCount); };
  const auto tag = [](size_t tile) { return static_cast<int>(tile % 32767); };
  stats.tilesResumed = static_cast<long long>(tiles.size() - todo.size());

  const BasisProjector projector(basis, header.latticeSize(), header.rowLength());
  struct Slot {
    size_t tile = 0;
    std::vector<float> rows, truth;
    Model part;
    TileEnergies energies;
    std::pair<long long, long long> rays;
  };
  // A fault-injection switch for the tests: the rank that starts this tile dies.
  const char* fault = std::getenv("ACPCA_FAULT_TILE");
  const long long faultTile = fault ? std::atoll(fault) : -1;
  long long rowsDone = 0;
  for (size_t t = 0; t < tiles.size(); ++t)
    if (todoMessage.data[t]) rowsDone += static_cast<long long>(tiles[t].rows.size());
  size_t next = 0, written = 0;  // into mine; into todo (rank 0)
  const auto wrote = [&](size_t tile) {
    rowsDone += static_cast<long long>(tiles[tile].rows.size());
    if (o.progress) o.progress(rowsDone, stats.rows);
  };
  // Rank 0: the other ranks' tiles that come before todo[end], in order.
  const auto receiveOthersBefore = [&](size_t end) {
    for (; written < end; ++written)
      if (owner(written) != 0) {
        writeBytes(tilePath(dir, todo[written]),
                   ranks::receiveBytes(owner(written), tag(todo[written])));
        wrote(todo[written]);
      }
  };
  const auto writePart = [&](const Slot& slot, const std::string& path) {
    ModelFileWriter part(path, head, ModelFileKind::Clusters);
    part.append(slot.part);
    if (!slot.truth.empty()) part.writeArray("ground_truth", slot.truth);
    part.finish(slot.part, slot.energies.attributes());
  };
  runOrderedPipeline<Slot>(
      o.tilesInFlight,
      [&](Slot& slot) {
        if (next >= mine.size()) return false;
        slot.tile = mine[next++];
        const Tile& t = tiles[slot.tile];
        if (rankCount > 1 && o.log)
          o.log(concat(ranks::prefix(), "starts tile ", slot.tile, " (pixels ", t.x0, ",", t.y0,
                       " to ", t.x0 + t.width - 1, ",", t.y0 + t.height - 1, ")"));
        return true;
      },
      [&](Slot& slot) {
        if (static_cast<long long>(slot.tile) == faultTile) std::raise(SIGKILL);
        slot.part = compressTile(tiles[slot.tile], source, projector, basis, o, truthSet, side,
                                 slot.rows, slot.truth, slot.energies, slot.rays);
      },
      [&](Slot& slot) {
        stats.occlusionRays += slot.rays.first, stats.pathRays += slot.rays.second;
        if (lead) {
          receiveOthersBefore(static_cast<size_t>(
              std::lower_bound(todo.begin(), todo.end(), slot.tile) - todo.begin()));
          writePart(slot, tilePath(dir, slot.tile));
          ++written;
          wrote(slot.tile);
        } else {
          // Written where this rank can (its temporary directory), sent as
          // bytes: the file rank 0 keeps is the one it would have written.
          const std::string local =
              (fs::temp_directory_path() / concat("acpca-tile-", ::getpid(), "-", slot.tile, ".h5"))
                  .string();
          writePart(slot, local);
          ranks::sendBytes(0, tag(slot.tile), readBytes(local));
          std::error_code ec;
          fs::remove(local, ec);
        }
        slot.part = Model();
      });
  if (lead) receiveOthersBefore(todo.size());
  stats.occlusionRays = ranks::sum(stats.occlusionRays);
  stats.pathRays = ranks::sum(stats.pathRays);
  if (!lead) {  // rank 0 assembles the model
    stats.seconds = watch.seconds();
    return stats;
  }
  stats.tileSeconds = watch.seconds() - stats.basisSeconds;
  if (stats.tilesResumed > 0)
    log(concat(stats.tilesResumed, " of ", tiles.size(), " tiles finished by an earlier run"));
  log(concat(tiles.size(), " tiles of ", side, "x", side, " rendered and compressed"));

  // Assemble the model from the tiles, in tile order.
  const double assembleStart = watch.seconds();
  {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec))
      stats.peakWorkBytes += static_cast<long long>(entry.file_size(ec));
  }
  ModelFileWriter writer(outPath, head);
  TileEnergies sum;
  const int maps = truthSet.maps();
  sum.truthDiff.assign(maps, 0.0), sum.truthNorm.assign(maps, 0.0);
  std::vector<std::vector<float>> truth(maps);
  if (!o.groundTruthDir.empty())
    for (auto& t : truth) t.assign(3 * static_cast<size_t>(stats.rows), 0.0f);
  for (size_t t = 0; t < tiles.size(); ++t) {
    TileEnergies e;
    e.truthDiff.assign(maps, 0.0), e.truthNorm.assign(maps, 0.0);
    std::map<std::string, double> extra = e.attributes();
    const std::string path = tilePath(dir, t);
    const Model part = readModelClusters(path, head, &extra);
    writer.append(part);
    sum.energy += extra["energy"];
    sum.globalResidual += extra["global_residual"];
    sum.errorEnergy += extra["error_energy"];
    for (int m = 0; m < maps; ++m) {
      sum.truthDiff[m] += extra[concat("truth_diff_", m)];
      sum.truthNorm[m] += extra[concat("truth_norm_", m)];
    }
    stats.frameBytes += part.frameBytes();
    if (!o.groundTruthDir.empty()) {
      const std::vector<long long>& rows = tiles[t].rows;
      const std::vector<float> values = readTileArray(path, "ground_truth", maps * rows.size() * 3);
      for (int m = 0; m < maps; ++m)
        for (size_t i = 0; i < rows.size(); ++i)
          for (int c = 0; c < 3; ++c)
            truth[m][3 * rows[i] + c] = values[(m * rows.size() + i) * 3 + c];
    }
  }
  for (int m = 0; m < maps; ++m) {
    const double error = sum.truthNorm[m] > 0 ? std::sqrt(sum.truthDiff[m] / sum.truthNorm[m])
                                              : std::sqrt(sum.truthDiff[m]);
    stats.imageErrors.emplace_back(truthSet.environments[m]->name(), error);
  }
  Model summary;
  summary.transportError =
      sum.energy > 0 ? std::sqrt(std::max(0.0, sum.errorEnergy) / sum.energy) : 0;
  summary.globalEnergyKept = sum.energy > 0 ? 1 - sum.globalResidual / sum.energy : 1;
  summary.compressSeconds = watch.seconds();
  summary.peakMemoryBytes = o.peakMemory ? o.peakMemory() : 0;
  stats.clusters = writer.clustersWritten();
  stats.costPerPixel = writer.totalCost() / std::max(1LL, stats.rows);
  writer.finish(summary);
  stats.transportError = summary.transportError;
  stats.globalEnergyKept = summary.globalEnergyKept;
  stats.frameBytes += static_cast<long long>(basis.basis.size()) * 4;
  for (int m = 0; m < maps && !o.groundTruthDir.empty(); ++m) {
    const Image image = composeImage(header, truth[m], Background::Env, *truthSet.environments[m],
                                     Eigen::Matrix3d::Identity());
    writeImage(image,
               (fs::path(o.groundTruthDir) / (truthSet.environments[m]->name() + ".exr")).string(),
               ImageFormat::Exr, 0);
  }
  std::error_code ec;
  fs::remove_all(dir, ec);  // the model is in place: the tiles are no longer needed
  stats.assembleSeconds = watch.seconds() - assembleStart;
  stats.seconds = watch.seconds();
  log(concat("assembled ", stats.clusters, " clusters in ", stats.assembleSeconds, " s"));
  return stats;
}

}  // namespace acpca
