#pragma once
// The streamed build (docs/architecture.md, "The streamed build"): scene ->
// model without the dense transport. A seeded sample of rows is rendered first
// and the global basis fitted to it; then the image is rendered tile by tile,
// each tile projected onto the basis and compressed with the tile as its root
// block, and kept as a file of clusters; the model is assembled from them in
// tile order. Memory holds a few tiles whatever the image size.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cluster/compress.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"

namespace acpca {

struct BuildOptions {
  PrecomputeOptions render;  ///< how rows are rendered, as precompute renders them
  /// adaptive-quad and block: the tiles are their root blocks (block side, 64
  /// by default), and the model is the one compress makes; cpca and
  /// adaptive-binary cluster each tile (a group of pixels, tileSide) on its
  /// own: CPCA with its share of the K clusters by rows, adaptive binary from
  /// `clusters` initial ones; global is refused. Global energy, sample rows,
  /// seed, tolerance and storage as compress takes them.
  CompressOptions compress;
  /// cpca, adaptive-binary: side of the tile groups (0: 256).
  int tileSide = 0;
  /// Continue an interrupted build from its finished tiles (same scene and
  /// settings); without it, what an earlier build left is started over.
  bool resume = false;
  /// What the note an interrupted build leaves says continues it (the caller's
  /// words for resuming).
  std::string resumeAdvice = "resuming the same build continues from them";
  /// Tiles in flight at once (each holds its rows in float).
  int tilesInFlight = 3;
  /// Lightings (`--env` specs) whose dense relight B = albedo (T L), the
  /// ground truth no file holds, is computed tile by tile from the rendered
  /// rows, with the model's image error against it (as eval measures it).
  std::vector<std::string> groundTruth;
  /// Where the ground-truth images go (EXR, one per lighting, composed as
  /// `relight` composes a transport's); empty: the errors alone.
  std::string groundTruthDir;
  /// Also write the dense transport the tiles render to this file, as
  /// precompute writes it (one process, not with resume: it needs every tile's
  /// rows, in order). Empty: none.
  std::string keepTransport;
  /// Called in order as tiles finish: (rows done, rows in total).
  std::function<void(long long, long long)> progress;
  /// Stage messages.
  std::function<void(const std::string&)> log;
  /// Called as this process starts each tile (its index): where tests stop a
  /// rank on purpose.
  std::function<void(long long tile)> beforeTile;

  /// The same options for view k of a scene of `views` (docs/scenes.md,
  /// "Several views"): the kept transport beside its path as STEM_vNN, the
  /// ground truths in a folder vNN of their own.
  BuildOptions forView(size_t k, size_t views) const;
};

struct BuildStats {
  long long rows = 0, tiles = 0, tilesResumed = 0;
  long long occlusionRays = 0, pathRays = 0;
  int globalBases = 0;
  double sampleEnergyKept = 0, heldOutEnergyKept = 0;
  double basisSeconds = 0;  ///< rendering the sample and fitting the basis
  double tileSeconds = 0;   ///< rendering, projecting and compressing the tiles
  double assembleSeconds = 0;
  double seconds = 0;
  long long clusters = 0;
  double costPerPixel = 0, transportError = 0, globalEnergyKept = 0;
  long long frameBytes = 0;
  long long peakWorkBytes = 0;  ///< largest size of the tile files on disk
  /// Per ground-truth lighting: its name and the model's relative L2 image
  /// error against the dense relight (occupied pixels, RGB).
  std::vector<std::pair<std::string, double>> imageErrors;
};

/// Validates the options (UserError / ParameterError before any work), builds
/// and writes the model atomically: no file at outPath unless complete. The
/// finished tiles wait in `<outPath>.tiles/` (removed once the model is in
/// place), which `resume` continues from.
/// What a build needs at most in memory (it writes tiles and the model, whose
/// size is known only as they are fitted).
/// The figures of one build, as `build --json` reports them.
nlohmann::json toJson(const BuildStats& stats);
/// The same in a line of words, for the log (with this process's peak memory).
std::string describeInWords(const BuildStats& stats);

ResourceNeed buildNeed(const Scene& scene, const std::string& outPath, const BuildOptions& o);

BuildStats buildStreamed(const Scene& scene, const std::string& outPath,
                         const BuildOptions& options);

}  // namespace acpca
