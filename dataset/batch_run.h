#pragma once
// One batch's run: what its views share while they relight one after another,
// the checks made before any frame, and one view's frames relit on every
// rank and written by rank 0.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/warning.h"
#include "dataset/batch_frames.h"
#include "dataset/batch_relight.h"
#include "dataset/frame_writing.h"
#include "transport/camera.h"

namespace acpca {

/// How much of the frames' lighting fell on directions a captured light
/// set has no cell for (the image cannot show it).
struct UncoveredLighting {
  /// Shares of a frame's energy below this are not worth a word.
  static constexpr double kNegligible = 1e-3;
  long long frames = 0;
  double largest = 0;
  void note(double share) {
    if (share <= kNegligible) return;
    ++frames;
    largest = std::max(largest, share);
  }
  void report() const {
    if (frames > 0)
      warn(concat(frames,
                  " frame(s) are lit partly from directions no captured light stands for "
                  "(up to ",
                  100 * largest, "% of a frame's lighting): their images leave that light out"));
  }
};

/// What the views of a batch share while they relight one after another.
struct BatchRun {
  BatchRun(const BatchRelightOptions& options, const BatchPlan& plan)
      : a(options), batch(plan.batch), formats(plan.formats), sets(plan.lightSets) {}
  const BatchRelightOptions& a;
  const bool batch;
  const std::vector<ImageFormat> formats;
  const std::vector<std::vector<LocalLight>> sets;
  std::vector<std::vector<std::string>> setSpecs;
  std::vector<EnvInput> inputs;
  std::vector<BatchFrame> viewFrames;       ///< each view's frames (the same for every view)
  std::optional<BatchManifests> manifests;  ///< rank 0 of a batch
  BatchStages stages;
  std::vector<double> msPerFrame;
  nlohmann::json outputs = nlohmann::json::array();
  nlohmann::json labels = nlohmann::json::array();
  size_t frames = 0;            ///< frames of the views done
  std::vector<Camera> cameras;  ///< each view's (none for captured light sets)
  UncoveredLighting uncovered;
  long long framesWithNegatives = 0;  ///< rank 0: frames written with values below zero
  NegativeClamp negatives;
  /// This rank's lamps: shadow rays traced, and covered pixels relit (rows x light sets).
  long long lampShadowRays = 0, lampPixels = 0;
  /// Of those, the maps' sources': rays, and covered pixels relit per source.
  long long sourceShadowRays = 0, sourcePixels = 0;
};

/// Refuses, before any frame, what a captured light set cannot do: show the
/// environment behind it (it has no camera) or take local lights (no
/// positions); the fast rotation resamples a cube lattice.
void requireLightingDomain(const TransportHeader& h, const BatchRun& run, const std::string& path);

/// Refuses, before any work, a batch that would write one file twice. Frame
/// names start with their index, so only a broken naming rule gets here.
void requireDistinctFrameFiles(const BatchRun& run, size_t views, int indexDigits);

/// Whether the view's file lights the maps' sources exactly: --sun on, exact
/// lamps asked for, and a file that holds its surfaces and direct light
/// apart. Where it cannot, one warning names the file and why, and the
/// sources stay in the maps, on the lattice.
bool sourcesLitExactly(const BatchRun& run, const RelightSource& source, const std::string& path);

/// One view's frames relit and (rank 0) written; returns its frame count.
size_t relightView(BatchRun& run, const RelightSource& source, BatchView view);

}  // namespace acpca
