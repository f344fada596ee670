#pragma once
// What a precompute is asked (PrecomputeOptions) and what it reports
// (PrecomputeStats): a leaf header, so that the precompute's pieces and the
// CLI's flags need nothing of the renderer itself.
#include <functional>
#include <string>

#include "core/enum_names.h"
#include "transport/transport_file.h"

namespace acpca {

/// Which camera samples of a pixel get shadow rays. Adaptive: all of them
/// where they disagree (a silhouette, a crease, two objects, a depth step),
/// else the centre alone, so a pixel inside one smooth surface costs one
/// sample; shadow edges inside such a pixel are point-sampled. Full: every
/// covered sample, shadow edges included, at spp times the cost.
enum class Antialiasing { Adaptive, Full };
inline constexpr EnumNames<Antialiasing, 2> kAntialiasingNames{
    "anti-aliasing", {{{Antialiasing::Adaptive, "adaptive"}, {Antialiasing::Full, "full"}}}};
/// Camera samples per pixel unless told otherwise: enough for silhouettes and
/// texture edges (docs/scenes.md, "Anti-aliasing").
inline constexpr int kDefaultSamplesPerPixel = 4;
/// Interreflections (docs/scenes.md, "Interreflections"): paths per traced
/// camera sample, and the visibility cache's cell as a fraction of the scene's
/// extent, unless told otherwise.
inline constexpr int kDefaultIndirectSamples = 64;
inline constexpr double kDefaultIndirectCacheCell = 1.0 / 1024;
inline constexpr int kMaxBounces = 16;
inline constexpr int kMaxIndirectSamples = 1 << 16;

struct PrecomputeOptions {
  int cubemapResolution = 32;
  /// Camera samples per pixel: the albedo is their mean, the row their
  /// luminance-weighted mean, the coverage their share that hits.
  int samplesPerPixel = kDefaultSamplesPerPixel;
  Antialiasing antialiasing = Antialiasing::Adaptive;
  int texelRays = 1;  ///< occlusion rays per texel (> 1: fractional visibility)
  Precision precision = Precision::F16;
  int threads = 0;  ///< 0: all cores
  /// Light that bounces off scene surfaces before reaching a pixel: up to this
  /// many bounces (0: direct light alone, the transport of docs/design.md section 4).
  int bounces = 0;
  int indirectSamples = kDefaultIndirectSamples;  ///< paths per traced camera sample
  /// Path vertices look up the visibility of a point in the same cell of this
  /// size (a fraction of the scene's extent) and facing the same way; 0: trace
  /// each vertex's own shadow rays (unbiased, and slow).
  double indirectCacheCell = kDefaultIndirectCacheCell;
  /// Called from one thread as rows are written: (rows done, rows in total).
  std::function<void(long long, long long)> progress;
  /// Lines worth a log (under MPI: which rank starts which image rows).
  std::function<void(const std::string&)> log;
  /// The same for the indirect cache: its pre-pass (image rows done, in total),
  /// then its visibility (points done, in total).
  std::function<void(long long, long long)> cacheProgress, cacheFillProgress;
  /// Start even when the disk or memory looks too small (precomputeNeed).
  bool force = false;
  /// Called as this process starts each image row (its index): where tests
  /// stop a rank on purpose, to see the job end cleanly.
  std::function<void(int imageRow)> beforeImageRow;
};

struct PrecomputeStats {
  long long triangles = 0;
  long long degenerateTriangles = 0;  ///< zero-area triangles left out
  long long occupiedPixels = 0;
  long long occlusionRays = 0;
  long long bytesWritten = 0;        ///< transport rows only
  double seconds = 0;                ///< wall time of the whole precompute
  double transportSeconds = 0;       ///< the occlusion-ray pass alone
  int threadsUsed = 0;               ///< distinct threads that computed rows
  long long supersampledPixels = 0;  ///< pixels that traced more than their centre sample
  int channels = 1;                  ///< rows per pixel: 3 when bounced light is coloured
  long long pathRays = 0;            ///< closest-hit rays of the indirect paths
  long long cachePoints = 0;         ///< points of the indirect visibility cache
  long long cacheRays = 0;           ///< their shadow rays (not in occlusionRays)
  double cacheSeconds = 0;           ///< the cache's pre-pass and tracing
  double raysPerSecond() const {
    return transportSeconds > 0 ? occlusionRays / transportSeconds : 0;
  }
};

}  // namespace acpca
