#pragma once
// Batch relighting: a model (or a transport, the dense ground truth) under
// every pair of lighting and rotation, written as images (one file, or a
// directory with one image per pair and a manifest.csv), with optional timing.
#include <algorithm>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dataset/batch_options.h"
#include "imageio/image_output.h"
#include "relight/image_composer.h"

namespace acpca {

/// The image formats to write: a comma-separated list of "exr", "png",
/// "png16" and "npy", or "both" (exr,png); empty picks EXR for a batch and
/// otherwise the output's extension (ParameterError when it has none).
std::vector<ImageFormat> imageFormatsFor(const std::string& format, const std::string& out,
                                         bool batch);

/// Where a batch's time went (seconds, on this rank). Writing runs on threads
/// of its own beside the relight: `writing` is their busy time, and
/// `waitingForWriting` the time the relight stood still for a full queue.
struct BatchStages {
  double open = 0;         ///< opening the model or transport
  double lighting = 0;     ///< the lightings integrated onto the lattice (rotation included)
  double projection = 0;   ///< V_g and the bases met by a group's lightings (models)
  double shading = 0;      ///< pixels relit (a transport: its pass over T)
  double localLights = 0;  ///< the local lights relit (once: the same in every frame)
  double sources = 0;      ///< the maps' sources lit exactly, frame by frame
  double background = 0;   ///< the background composed under each frame
  double writing = 0;      ///< frames encoded and written (writing threads)
  double waitingForWriting = 0;
  double wall = 0;  ///< the whole batch
  /// Each stage by its JSON key, in the order they come, wall last.
  std::vector<std::pair<const char*, double>> named() const;
  nlohmann::json json(long long frames) const;
};

struct BatchRelightResult {
  std::string method;  ///< the model's, or "dense"
  long long frames = 0;
  std::vector<double> msPerFrame;  ///< every timed frame
  double bytesPerFrame = 0;
  std::vector<std::string> failed;    ///< maps that could not be loaded (batch only)
  long long framesWithNegatives = 0;  ///< frames whose values went below zero
  NegativeClamp negatives;            ///< all their negative values together
  BatchStages stages;
  nlohmann::json json;  ///< what `relight --json` writes
  std::string summary;  ///< one line: frames, median ms, bytes, GB/s
};

/// Checks the options that cost nothing to check (ParameterError, UserError
/// for a light path) and parses every light and format spec, once.
BatchPlan planBatchRelight(const BatchRelightOptions& options);

/// Relights and writes every frame. Frames go in groups of 32, each group one
/// pass over T for a transport, so memory stays flat for any count. Under
/// `mpirun -np K` the frames are dealt round robin and rank 0 writes them all
/// (the same files for any K; the other ranks return without figures). In a batch
/// a map that cannot be loaded is skipped (and listed in `failed`); the images
/// of the others are written.
BatchRelightResult relightBatch(const BatchRelightOptions& options, const BatchPlan& plan);
/// The same, planned here.
BatchRelightResult relightBatch(const BatchRelightOptions& options);

/// Throws UserError listing the maps of a batch of `maps` that could not be
/// used (the others were written); nothing when every map was.
void refuseFailedMaps(const BatchRelightResult& result, size_t maps);

}  // namespace acpca
