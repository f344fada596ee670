#pragma once
// What a batch relight is asked to do (batch_relight.h runs it): a leaf
// header, so that what reads the options (dataset_identity.h, the CLI's
// flags) needs nothing of the batch itself.
#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dataset/pixel_labels.h"
#include "imageio/image_output.h"
#include "lighting/lighting.h"
#include "lighting/lighting_sampler.h"
#include "lighting/local_light.h"
#include "lighting/map_sources.h"
#include "lighting/rotation.h"
#include "relight/image_composer.h"
#include "relight/lamp_light.h"
#include "relight/local_relight.h"
#include "relight/rank_limit.h"

namespace acpca {

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
  /// Local lights (lighting/local_light.h grammar), added to every frame;
  /// without envs they light the frames alone. A light whose numbers sweep
  /// (A:B:S, expandLightSweep) makes a frame per value (per combination).
  std::vector<std::string> lights;
  /// Models: texels of direction within which a cluster's pixels share a
  /// light's direction taps (relight/local_relight.h; 0: every pixel its own).
  double anchorSpread = kAnchorSpreadTexels;
  /// Lamps: exact where the file allows (relight/lamp_light.h), or the
  /// lattice's; a sphere lamp's rays per camera sample in a penumbra.
  LampSettings lamps;
  /// --sun: how each map's compact bright sources are found and split off
  /// to be lit exactly (lighting/map_sources.h); none: all through the lattice.
  std::optional<SourceFinding> sources = SourceFinding{};
  /// A light path file (local_light.h, readLightPath): every map x rotation
  /// is relit under each line's lights (with `lights` added), line by line.
  std::string lightPath;
  std::vector<EnvRotation> rotations{EnvRotation{}};
  /// Lightings drawn from `envs` instead of every map x rotation
  /// (lighting/lighting_sampler.h): count > 0 makes frames sample_NNNNN.
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
  /// Per-pixel labels (dataset/pixel_labels.h): the view's once (labels.exr
  /// in a batch's directory, else OUT_labels.exr beside the image), and with
  /// shading, each frame's (FRAME_shading.exr).
  std::vector<Aov> aovs;
  LabelFormat labelFormat = LabelFormat::Exr;
  /// Each frame's lattice lighting as a lat-long EXR (FRAME_lighting.exr):
  /// the radiance the frame was relit under, after rotation, before exposure.
  bool lightingImages = false;
  /// > 0: frames packed N to a tar, WebDataset style (dataset/batch_shards.h).
  long long shardSize = 0;
  /// COLMAP's text model (sparse/0) beside transforms.json (dataset/camera_files.h).
  bool colmap = false;
  RankLimit maxRank;  ///< models only
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

/// What a batch's specs say, parsed once by planBatchRelight (batch_relight.h)
/// and taken by every later step: no spec is parsed twice in a run, and the
/// manifest writes the lights from here.
struct BatchPlan {
  bool batch = false;                ///< a directory of frames (BatchRelightOptions::batch)
  std::vector<ImageFormat> formats;  ///< what each frame is written as
  /// Each frame's local lights: every combination of the --light sweeps (one
  /// set, maybe empty, when none sweeps), added to each light-path line.
  std::vector<std::vector<LocalLight>> lightSets;
};

}  // namespace acpca
