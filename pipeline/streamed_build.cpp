#include "pipeline/streamed_build.h"

#include <unistd.h>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "cluster/global_basis.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_guard.h"
#include "core/interrupt_cleanup.h"
#include "core/ordered_pipeline.h"
#include "core/rank_gather.h"
#include "core/ranks.h"
#include "core/resources.h"
#include "core/stopwatch.h"
#include "core/text.h"
#include "imageio/image_output.h"
#include "model/model_file.h"
#include "pipeline/ground_truth.h"
#include "pipeline/kept_transport.h"
#include "pipeline/sampled_basis.h"
#include "pipeline/tile_compression.h"
#include "pipeline/tile_files.h"
#include "pipeline/tile_plan.h"
#include "precompute/precompute_report.h"
#include "precompute/scene_views.h"
#include "relight/image_composer.h"

namespace acpca {

namespace fs = std::filesystem;

BuildOptions BuildOptions::forView(size_t k, size_t views) const {
  BuildOptions view = *this;
  if (!keepTransport.empty()) view.keepTransport = viewOutputPath(keepTransport, k, views);
  if (!groundTruthDir.empty() && views > 1)
    view.groundTruthDir = (fs::path(groundTruthDir) / viewName(k)).string();
  return view;
}

namespace {

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
  if (!o.keepTransport.empty() && o.resume)
    throw ParameterError("keep transport", o.keepTransport,
                         "cannot resume: an interrupted build kept no rows of its finished tiles");
  if (!o.keepTransport.empty() && ranks::distributed())
    throw ParameterError("keep transport", o.keepTransport,
                         "runs in one process: over MPI ranks every rank's rows would cross the "
                         "network to rank 0 (a distributed precompute writes the transport)");
}

/// The model's settings, as compress records them, plus how its rows were made.
/// The compress settings a `compress` of the same options records, then how
/// the rows were rendered and tiled (docs/formats.md).
std::string settingsJson(const BuildOptions& o, const Scene& scene, int tile, int globalBases) {
  nlohmann::json settings = compressSettings(o.compress, globalBases);
  settings.update(toJson(o.render));
  settings["source"] = concat("build of ", scene.name);
  settings["streamed"] = true;
  settings["tile"] = tile;
  return settings.dump();
}

}  // namespace

nlohmann::json toJson(const BuildStats& s) {
  nlohmann::json errors = nlohmann::json::object();
  for (const auto& [name, error] : s.imageErrors) errors[name] = error;
  return {{"rows", s.rows},
          {"tiles", s.tiles},
          {"tiles_resumed", s.tilesResumed},
          {"global_bases", s.globalBases},
          {"sample_energy_kept", s.sampleEnergyKept},
          {"held_out_energy_kept", s.heldOutEnergyKept},
          {"clusters", s.clusters},
          {"cost_per_pixel", s.costPerPixel},
          {"transport_error", s.transportError},
          {"global_energy_kept", s.globalEnergyKept},
          {"bytes_per_frame", s.frameBytes},
          {"occlusion_rays", s.occlusionRays},
          {"path_rays", s.pathRays},
          {"basis_seconds", s.basisSeconds},
          {"tile_seconds", s.tileSeconds},
          {"assemble_seconds", s.assembleSeconds},
          {"seconds", s.seconds},
          {"work_bytes", s.peakWorkBytes},
          {"image_errors", errors}};
}

std::string describeInWords(const BuildStats& s) {
  return concat(s.clusters, " clusters over ", s.tiles, " tiles, N = ", s.globalBases, ", ",
                s.costPerPixel, " per pixel, transport error ", s.transportError, ", ",
                formatBytes(s.frameBytes), " read per frame; ", s.seconds, " s (basis ",
                s.basisSeconds, " s, tiles ", s.tileSeconds, " s, assembly ", s.assembleSeconds,
                " s), peak memory ", formatBytes(peakMemoryBytes()), ", tiles on disk at most ",
                formatBytes(s.peakWorkBytes));
}

ResourceNeed buildNeed(const Scene& scene, const std::string& outPath, const BuildOptions& o) {
  // What precompute holds, and the rows of the basis sample and of the tiles
  // in flight, in float, instead of a transport on disk.
  ResourceNeed need = precomputeNeed(scene, outPath, o.render);
  const long long rowBytes = 6LL * o.render.cubemapResolution * o.render.cubemapResolution * 4 *
                             (o.render.bounces > 0 ? 3 : 1);
  const long long side = tileSide(o);
  const long long pixels =
      static_cast<long long>(scene.camera.size.width) * scene.camera.size.height;
  need.what = concat("a streamed build of ", scene.camera.size.width, "x", scene.camera.size.height,
                     " pixels");
  need.diskBytes = need.largestFile = 0;  // the model's size is known only once it is fitted
  need.memoryAdvice =
      "render a smaller image, or hold fewer or smaller tiles at once, or fewer sample rows";
  need.memoryBytes += (std::min<long long>(o.compress.sampleRows, pixels) +
                       std::min(pixels, o.tilesInFlight * side * side)) *
                      rowBytes;
  return need;
}

namespace {

/// Before any work: nothing written may replace what the build reads, the
/// disk and memory suffice, and every output's directory exists.
void checkOutputs(const Scene& scene, const std::string& outPath, const BuildOptions& o) {
  std::vector<std::string> inputs = scene.files;
  inputs.insert(inputs.end(), o.groundTruth.begin(), o.groundTruth.end());
  refuseOutputOverInputs(outPath, inputs);
  refuseOutputOverInputs(o.keepTransport, inputs);
  refuseDirectoryOverInputs(o.groundTruthDir, inputs);
  if (!o.keepTransport.empty() && !outPath.empty())
    refuseOutputOverInputs(o.keepTransport, {outPath});
  requireResources(buildNeed(scene, outPath, o), o.render.force);
  { AtomicOutput check(outPath); }  // the output's directory exists, before any work
  if (!o.keepTransport.empty()) AtomicOutput check(o.keepTransport);
  if (!o.groundTruthDir.empty()) createOutputDirectory(o.groundTruthDir);
}

/// Rank 0 renders the basis sample and fits the global basis; every rank
/// gets the same values.
GlobalBasis fitAndShareBasis(const RowSource& source, const CompressOptions& c, BuildStats& stats) {
  GlobalBasis basis;
  if (ranks::rank() == 0) {
    std::pair<long long, long long> rays{0, 0};
    basis = fitBasis(source, {c.globalEnergy, c.sampleRows, c.seed}, rays);
    stats.occlusionRays += rays.first, stats.pathRays += rays.second;
  }
  shareBasis(basis);
  stats.globalBases = basis.globalBases();
  stats.sampleEnergyKept = basis.sampleEnergyKept;
  stats.heldOutEnergyKept = basis.heldOutEnergyKept;
  return basis;
}

/// What every tile file and the model share: the image, the basis, the
/// settings and the storage.
Model modelHead(const TransportHeader& header, const GlobalBasis& basis, const BuildOptions& o,
                std::string settings) {
  Model head;
  head.geometry = header;
  head.method = methodName(o.compress.method);
  head.settings = std::move(settings);
  head.globalBasis = basis.basis;
  head.hasMean = keepsMean(o.compress.method);
  head.precision = o.compress.coeffs;
  head.basisPrecision = o.compress.bases;
  return head;
}

/// Rank 0 prepares the work directory (a resumed build must share the
/// settings, the image's rows and the basis) and every rank learns which
/// tiles are left to do.
std::vector<size_t> tilesLeftToDo(const std::string& dir, size_t tileCount, const Model& head,
                                  const BuildOptions& o) {
  const TransportHeader& header = head.geometry;
  const Eigen::MatrixXf& basis = head.globalBasis;
  const bool lead = ranks::rank() == 0;
  std::uint64_t hash = fingerprint(header.pixels.data(), header.pixels.size() * 4);
  hash = fingerprint(header.albedo.data(), header.albedo.size() * 4, hash);
  hash = fingerprint(basis.data(), basis.size() * 4, hash);
  // Rank 0 keeps the work directory and says which tiles are left to do.
  std::vector<char> done(tileCount, 0);
  if (lead) {
    prepareWorkDirectory(dir, head.settings + "\n" + std::to_string(hash) + "\n", o.resume, o.log);
    interrupt::setInterruptNote(concat("finished tiles are kept in ", dir, ": ", o.resumeAdvice));
    for (size_t t = 0; t < tileCount; ++t) {
      std::error_code ec;
      done[t] = o.resume && fs::exists(tilePath(dir, t), ec);
    }
  }
  ranks::broadcast(done);
  // Tiles left to do are dealt round robin; rank 0 writes every finished
  // tile, its own and those the others send; a tile's file is the same bytes
  // whoever made it, so nothing depends on the rank count.
  std::vector<size_t> todo;
  for (size_t t = 0; t < tileCount; ++t)
    if (!done[t]) todo.push_back(t);
  return todo;
}

/// The model from the finished tiles, in tile order, with its errors and
/// (when asked) the ground-truth images; `seconds` is the build's time so far.
void assembleModel(const std::string& outPath, const std::string& dir,
                   const std::vector<Tile>& tiles, const Model& head, const GlobalBasis& basis,
                   const GroundTruth& truthSet, const BuildOptions& o, double seconds,
                   BuildStats& stats) {
  const TransportHeader& header = head.geometry;
  {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec))
      stats.peakWorkBytes += static_cast<long long>(entry.file_size(ec));
  }
  ModelSizes sizes;  // the tiles' sizes first: the model's arrays are written whole-sized
  for (size_t t = 0; t < tiles.size(); ++t)
    sizes += readModelClusterSizes(tilePath(dir, t), basis.globalBases());
  ModelFileWriter writer(outPath, head, sizes);
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
  summary.compressSeconds = seconds;
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
}

/// Every tile left to do, rendered, projected and compressed by the rank it
/// is dealt to (round robin), kept as a file in `dir` by rank 0; with
/// --keep-transport the rows also go to the transport file.
void compressTiles(const std::vector<Tile>& tiles, const std::vector<size_t>& todo,
                   const RowSource& source, const GlobalBasis& basis, const GroundTruth& truthSet,
                   const Model& head, const std::string& dir, const BuildOptions& o,
                   BuildStats& stats) {
  const TransportHeader& header = source.header();
  const int rankCount = ranks::count();
  const bool lead = ranks::rank() == 0;
  const std::vector<long long> mine = ranks::itemsOfThisRank(static_cast<long long>(todo.size()));
  constexpr int kTileTag = 1;

  const BasisProjector projector(basis, header.latticeSize(), header.rowLength());
  struct Slot {
    long long item = 0;  ///< into todo
    size_t tile = 0;
    std::vector<float> rows, truth;
    Model part;
    TileEnergies energies;
    std::pair<long long, long long> rays;
  };
  long long rowsDone = stats.rows;  // the resumed tiles' rows, then each finished tile's
  for (size_t t : todo) rowsDone -= static_cast<long long>(tiles[t].rows.size());
  size_t next = 0;          // into mine
  std::mutex progressLock;  // rank 0 counts its own tiles and those it receives
  const auto wrote = [&](size_t tile) {
    std::lock_guard<std::mutex> lock(progressLock);
    rowsDone += static_cast<long long>(tiles[tile].rows.size());
    if (o.progress) o.progress(rowsDone, stats.rows);
  };
  // Rank 0 takes the other ranks' tiles as they arrive and in any order (each
  // is a file of its own; the model is assembled in tile order): a sender
  // waits for none of rank 0's tiles, and a slow tile holds up only its own
  // rank. Only the receiving thread writes those bytes (no HDF5 there, which
  // is not thread-safe).
  ranks::Gather<char> gather(
      static_cast<long long>(todo.size()), ranks::GatherOrder::Arrival,
      [&](long long item, std::vector<char>& bytes) {
        writeBytes(tilePath(dir, todo[item]), bytes);
        wrote(todo[item]);
      },
      kTileTag);
  const auto writePart = [&](const Slot& slot, const std::string& path) {
    ModelFileWriter part(path, head, ModelSizes::of(slot.part), ModelFileKind::Clusters);
    part.append(slot.part);
    if (!slot.truth.empty()) part.writeArray("ground_truth", slot.truth);
    part.finish(slot.part, slot.energies.attributes());
  };
  std::optional<KeptTransport> kept;
  if (!o.keepTransport.empty()) kept.emplace(o.keepTransport, header, tiles);
  runOrderedPipeline<Slot>(
      o.tilesInFlight,
      [&](Slot& slot) {
        if (next >= mine.size()) return false;
        slot.item = mine[next++];
        slot.tile = todo[slot.item];
        const Tile& t = tiles[slot.tile];
        if (rankCount > 1 && o.log)
          o.log(concat(ranks::prefix(), "starts tile ", slot.tile, " (pixels ", t.x0, ",", t.y0,
                       " to ", t.x0 + t.width - 1, ",", t.y0 + t.height - 1, ")"));
        return true;
      },
      [&](Slot& slot) {
        if (o.beforeTile) o.beforeTile(static_cast<long long>(slot.tile));
        slot.part = compressTile(tiles[slot.tile], source, projector, basis, o, truthSet, slot.rows,
                                 slot.truth, slot.energies, slot.rays);
      },
      [&](Slot& slot) {
        stats.occlusionRays += slot.rays.first, stats.pathRays += slot.rays.second;
        if (lead) {
          writePart(slot, tilePath(dir, slot.tile));
          if (kept) kept->add(slot.tile, slot.rows.data());
          wrote(slot.tile);
        } else {
          // Written where this rank can (its temporary directory), sent as
          // bytes: the file rank 0 keeps is the one it would have written.
          const std::string local =
              (fs::temp_directory_path() / concat("acpca-tile-", ::getpid(), "-", slot.tile, ".h5"))
                  .string();
          writePart(slot, local);
          std::vector<char> bytes = readBytes(local);
          gather.put(slot.item, bytes);
          std::error_code ec;
          fs::remove(local, ec);
        }
        slot.part = Model();
      });
  gather.finish();
  if (kept) {
    kept->finish();
    if (o.log) o.log(concat("wrote the transport to ", o.keepTransport));
  }
}

}  // namespace

BuildStats buildStreamed(const Scene& scene, const std::string& outPath, const BuildOptions& o) {
  validate(o);
  const Stopwatch watch;
  const auto log = [&](const std::string& s) {
    if (o.log && ranks::rank() == 0)  // stages once; every rank names its tiles
      o.log(concat("[", std::fixed, std::setprecision(1), watch.seconds(), " s] ", s));
  };
  BuildStats stats;
  checkOutputs(scene, outPath, o);
  GroundTruth truthSet = loadGroundTruth(o.groundTruth);

  const RowSource source(scene, o.render);
  const TransportHeader& header = source.header();
  layOutGroundTruth(truthSet, header.cubemapResolution, header.channels);
  stats.rows = header.rows();
  log(concat("G-buffer: ", header.rows(), " occupied pixels"));

  const CompressOptions& c = o.compress;
  const bool lead = ranks::rank() == 0;
  const GlobalBasis basis = fitAndShareBasis(source, c, stats);
  stats.basisSeconds = watch.seconds();
  log(concat("global basis: N = ", basis.globalBases(), " of ", basis.activeDirections,
             " directions the sample sees, ", basis.sampleEnergyKept, " of the sample's energy (",
             basis.heldOutEnergyKept, " on held-out rows)"));

  const int side = tileSide(o);
  const std::vector<Tile> tiles = planTiles(header.camera.size, header.pixels, side);
  stats.tiles = static_cast<long long>(tiles.size());
  const Model head = modelHead(header, basis, o, settingsJson(o, scene, side, basis.globalBases()));

  const std::string dir = buildWorkDirectory(outPath);
  const std::vector<size_t> todo = tilesLeftToDo(dir, tiles.size(), head, o);
  stats.tilesResumed = static_cast<long long>(tiles.size() - todo.size());
  compressTiles(tiles, todo, source, basis, truthSet, head, dir, o, stats);
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

  const double assembleStart = watch.seconds();
  assembleModel(outPath, dir, tiles, head, basis, truthSet, o, watch.seconds(), stats);
  std::error_code ec;
  fs::remove_all(dir, ec);  // the model is in place: the tiles are no longer needed
  interrupt::setInterruptNote("");
  stats.assembleSeconds = watch.seconds() - assembleStart;
  stats.seconds = watch.seconds();
  log(concat("assembled ", stats.clusters, " clusters in ", stats.assembleSeconds, " s"));
  return stats;
}

}  // namespace acpca
