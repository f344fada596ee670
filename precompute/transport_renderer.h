#pragma once
// The precompute: fills the transport row of every occupied pixel with Embree
// and streams it to a transport file (docs/design.md section 4).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/resources.h"
#include "precompute/scene.h"
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

/// What precompute needs at most: every pixel a row (three with bounced
/// light) on disk, and its camera samples, row headers and scene in memory.
ResourceNeed precomputeNeed(const Scene& scene, const std::string& outPath,
                            const PrecomputeOptions& options);

/// Validates the options (UserError on bad values) and writes the transport file
/// atomically: on any failure no file appears at outPath.
PrecomputeStats precomputeTransport(const Scene& scene, const std::string& outPath,
                                    const PrecomputeOptions& options);

/// The rows of chosen pixels on demand, for a build that never writes the
/// whole transport: the G-buffer, lattice, shadow rays and (with bounces) the
/// indirect cache are built once, in the caller's TBB arena; each call renders
/// only the rows asked for, each exactly as precomputeTransport renders it.
class RowSource {
 public:
  /// Validates the options (UserError on bad values); options.threads is not
  /// used (the caller's arena is).
  RowSource(const Scene& scene, const PrecomputeOptions& options);
  ~RowSource();
  /// The header a transport file of the scene would carry: every occupied pixel.
  const TransportHeader& header() const;
  int rowLength() const { return header().rowLength(); }
  /// Fills out (rows.size() x rowLength floats) with the rows of these row
  /// indices, rounded through half when the header's precision is f16 (as the
  /// file stores them), in parallel. Returns the occlusion and path rays traced.
  std::pair<long long, long long> render(const std::vector<long long>& rows, float* out) const;
  /// Triangles, degenerate triangles, the indirect cache's figures.
  const PrecomputeStats& setupStats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acpca
