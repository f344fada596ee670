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

#include "relight/image_output.h"
#include "relight/lighting.h"
#include "relight/lighting_sampler.h"
#include "relight/local_relight.h"
#include "relight/model_relighter.h"
#include "relight/pixel_labels.h"
#include "relight/rotation.h"

namespace acpca {

/// A limit on each cluster's rank: "K" keeps the first K bases, a fraction in
/// (0, 1) or a percentage ("50%") that share of each cluster's. Throws a
/// ParameterError ("maximum rank") for anything else.
void applyRankLimit(const std::string& text, ModelRelighter& relighter);

/// The image formats to write: a comma-separated list of "exr", "png",
/// "png16" and "npy", or "both" (exr,png); empty picks EXR for a batch and
/// otherwise the output's extension (ParameterError when it has none).
std::vector<ImageFormat> imageFormatsFor(const std::string& format, const std::string& out,
                                         bool batch);

/// What a batch writes unless told otherwise: codecs that keep up with the
/// relighter (docs/architecture.md, "Batches"; measured in docs/results.md).
inline constexpr ExrCompression kBatchExrCompression = ExrCompression::Rle;
inline constexpr int kBatchPngLevel = 1;

struct BatchRelightOptions {
  std::string input;  ///< model or transport file (the first view)
  /// Further views of the scene (a scene file's "cameras" make
  /// STEM_v01.h5, ...): each is relit under every lighting in turn, its
  /// frames named vNN_..., its labels labels_vNN.
  std::vector<std::string> moreViews;
  std::vector<std::string> viewInputs() const {
    std::vector<std::string> all{input};
    all.insert(all.end(), moreViews.begin(), moreViews.end());
    return all;
  }
  std::vector<std::string> envs;  ///< lighting specs or image files (may be empty with lights)
  /// Local lights (relight/local_light.h grammar), added to every frame;
  /// without envs they light the frames alone. A light whose numbers sweep
  /// (A:B:S, expandLightSweep) makes a frame per value (per combination).
  std::vector<std::string> lights;
  /// Models: texels of direction within which a cluster's pixels share a
  /// light's direction taps (relight/local_relight.h; 0: every pixel its own).
  double anchorSpread = kAnchorSpreadTexels;
  /// A light path file (local_light.h, readLightPath): every map x rotation
  /// is relit under each line's lights (with `lights` added), line by line.
  std::string lightPath;
  std::vector<EnvRotation> rotations{EnvRotation{}};
  /// Lightings drawn from `envs` instead of every map x rotation
  /// (relight/lighting_sampler.h): count > 0 makes frames sample_NNNNN.
  LightingSampling sampling;
  std::string out;     ///< an image, or a directory when batch
  std::string format;  ///< exr, png, both; empty: see imageFormatsFor
  Background background = Background::Env;
  RotationMode rotationMode = RotationMode::Exact;
  double exposure = 0;
  bool exrFloat = false;
  /// The EXR codec; unset: zips for one image, kBatchExrCompression for a batch.
  std::optional<ExrCompression> exrCompression;
  int pngLevel = kBatchPngLevel;      ///< PNG deflate level, 0-9
  ToneCurve tone = ToneCurve::Clamp;  ///< PNG output's tone curve
  /// Per-pixel labels (relight/pixel_labels.h): the view's once (labels.exr
  /// in a batch's directory, else OUT_labels.exr beside the image), and with
  /// shading, each frame's (FRAME_shading.exr).
  std::vector<Aov> aovs;
  LabelFormat labelFormat = LabelFormat::Exr;
  /// Each frame's lattice lighting as a lat-long EXR (FRAME_lighting.exr):
  /// the radiance the frame was relit under, after rotation, before exposure.
  bool lightingImages = false;
  std::string maxRank;  ///< see applyRankLimit; models only
  /// Write the raw reconstruction, negative values and all, instead of
  /// clamping frames and shading at zero (docs/design.md, section 6).
  bool keepNegative = false;
  int timingRepeats = 0;  ///< > 0: after a warm-up, time that many repeats
  bool force = false;     ///< write even when the frames look too large for the disk
  std::function<void(long long done, long long total)> progress;
  std::function<void(const std::string&)> warn;  ///< a map skipped in a batch
  /// Whether the lights change from frame to frame: a light path or a sweep.
  bool movesLights() const {
    return !lightPath.empty() || std::any_of(lights.begin(), lights.end(), isLightSweep);
  }
  bool batch() const {
    return envs.size() > 1 || rotations.size() > 1 || movesLights() || sampling.count > 0 ||
           !moreViews.empty();
  }
};

/// Where a batch's time went (seconds, on this rank). Writing runs on threads
/// of its own beside the relight: `writing` is their busy time, and
/// `waitingForWriting` the time the relight stood still for a full queue.
struct BatchStages {
  double open = 0;         ///< opening the model or transport
  double lighting = 0;     ///< the lightings integrated onto the lattice (rotation included)
  double projection = 0;   ///< V_g and the bases met by a group's lightings (models)
  double shading = 0;      ///< pixels relit (a transport: its pass over T)
  double localLights = 0;  ///< the local lights relit (once: the same in every frame)
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

/// Checks the options that cost nothing to check (ParameterError).
void validateBatchRelight(const BatchRelightOptions& options);

/// Relights and writes every frame. Frames go in groups of 32, each group one
/// pass over T for a transport, so memory stays flat for any count. Under
/// `mpirun -np K` the frames are dealt round robin and rank 0 writes them all
/// (the same files for any K; the other ranks return without figures). In a batch
/// a map that cannot be loaded is skipped (and listed in `failed`); the images
/// of the others are written.
BatchRelightResult relightBatch(const BatchRelightOptions& options);

/// Throws UserError listing the maps of a batch of `maps` that could not be
/// used (the others were written); nothing when every map was.
void refuseFailedMaps(const BatchRelightResult& result, size_t maps);

}  // namespace acpca
