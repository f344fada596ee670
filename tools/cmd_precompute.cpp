// `adaptive-cpca precompute`: scene -> transport file (Embree).
#include <iostream>
#include <optional>

#include "core/ranks.h"
#include "precompute/render/scene.h"
#include "precompute/render/transport_renderer.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct PrecomputeArgs {
  CommonOptions common;
  std::string scene, out, size, camera, precision = "f16", antialiasing = "adaptive";
  int cubemap = 32, spp = kDefaultSamplesPerPixel, texelRays = 1;
  int bounces = 0, indirectSamples = kDefaultIndirectSamples;
  double indirectCache = kDefaultIndirectCacheCell;
};

void run(const PrecomputeArgs& a) {
  // Reject bad options before any work.
  PrecomputeOptions options;
  options.cubemapResolution = a.cubemap;
  options.samplesPerPixel = a.spp;
  options.antialiasing = kAntialiasingNames.parse(a.antialiasing);
  options.texelRays = a.texelRays;
  options.precision = parsePrecision(a.precision);
  options.threads = a.common.threads;
  options.bounces = a.bounces;
  options.indirectSamples = a.indirectSamples;
  options.indirectCacheCell = a.indirectCache;
  Scene scene = loadScene(a.scene);
  if (!a.size.empty()) scene.camera.size = parseSize(a.size, "--size");
  applyCameraSpec(scene, a.camera);
  scene.validate();

  if (ranks::rank() == 0)
    for (const auto& w : samplingWarnings(scene, options)) std::cerr << "warning: " << w << "\n";

  ThreadLimit limit(a.common.threads);
  // Under mpirun every rank renders; rank 0 writes and reports.
  const bool lead = ranks::rank() == 0;
  const bool quiet = a.common.quiet || !lead;
  Progress progress("precompute " + scene.name, "rows", quiet);
  std::optional<Progress> cacheProgress, cacheFillProgress;
  options.cacheProgress = [&](long long done, long long total) {
    if (!cacheProgress) cacheProgress.emplace("indirect cache: paths", "image rows", quiet);
    cacheProgress->update(done, total);
    if (done == total) cacheProgress->finish();
  };
  options.cacheFillProgress = [&](long long done, long long total) {
    if (!cacheFillProgress)
      cacheFillProgress.emplace("indirect cache: visibility", "points", quiet);
    cacheFillProgress->update(done, total);
    if (done == total) cacheFillProgress->finish();
  };
  options.progress = [&](long long done, long long total) { progress.update(done, total); };
  options.log = [&](const std::string& line) {
    // One write per line: the ranks share mpirun's stderr.
    if (!a.common.quiet) std::cerr << ("precompute: " + line + "\n");
  };
  const PrecomputeStats stats = precomputeTransport(scene, a.out, options);
  progress.finish();
  if (!lead) return;

  const double raysPerSecond = stats.raysPerSecond();
  if (!a.common.quiet)
    std::cerr << "wrote " << a.out << ": " << scene.camera.size.width << "x"
              << scene.camera.size.height << ", " << stats.occupiedPixels << " occupied pixels, "
              << 6 * a.cubemap * a.cubemap << " directions, " << formatBytes(stats.bytesWritten)
              << " of rows; " << stats.occlusionRays << " occlusion rays in "
              << stats.transportSeconds << " s (" << raysPerSecond / 1e6 << " M rays/s, "
              << stats.threadsUsed << " threads"
              << (ranks::distributed() ? concat(" over ", ranks::count(), " ranks") : std::string())
              << "), total " << stats.seconds << " s, peak memory "
              << formatBytes(peakMemoryBytes()) << "; " << stats.supersampledPixels
              << " pixels traced at " << a.spp << " samples, the rest at 1\n";
  if (a.bounces > 0 && !a.common.quiet)
    std::cerr << "indirect light: " << a.bounces << " bounce(s), " << a.indirectSamples
              << " paths per traced sample, " << stats.pathRays << " path rays; "
              << (stats.channels == 3 ? "R, G and B rows (coloured surfaces)"
                                      : "one row per pixel (grey surfaces)")
              << "; visibility cache: "
              << (a.indirectCache > 0 ? concat(stats.cachePoints, " points, ", stats.cacheRays,
                                               " rays, ", stats.cacheSeconds, " s")
                                      : std::string("off (exact shadow rays at every vertex)"))
              << "\n";
  if (stats.degenerateTriangles > 0 && !a.common.quiet)
    std::cerr << "note: " << stats.degenerateTriangles
              << " zero-area triangles were left out (they cover nothing)\n";
  writeJson(a.common.jsonPath, {{"out", a.out},
                                {"scene", scene.name},
                                {"width", scene.camera.size.width},
                                {"height", scene.camera.size.height},
                                {"cubemap", a.cubemap},
                                {"triangles", stats.triangles},
                                {"degenerate_triangles", stats.degenerateTriangles},
                                {"occupied_pixels", stats.occupiedPixels},
                                {"occlusion_rays", stats.occlusionRays},
                                {"spp", a.spp},
                                {"antialiasing", a.antialiasing},
                                {"supersampled_pixels", stats.supersampledPixels},
                                {"rays_per_second", raysPerSecond},
                                {"transport_seconds", stats.transportSeconds},
                                {"seconds", stats.seconds},
                                {"threads_used", stats.threadsUsed},
                                {"ranks", ranks::count()},
                                {"row_bytes", stats.bytesWritten},
                                {"bounces", a.bounces},
                                {"indirect_samples", a.indirectSamples},
                                {"indirect_cache_cell", a.indirectCache},
                                {"channels", stats.channels},
                                {"path_rays", stats.pathRays},
                                {"cache_points", stats.cachePoints},
                                {"cache_rays", stats.cacheRays},
                                {"cache_seconds", stats.cacheSeconds},
                                {"peak_memory_bytes", peakMemoryBytes()}});
}

}  // namespace

void registerPrecompute(CLI::App& app) {
  auto args = std::make_shared<PrecomputeArgs>();
  auto* sub = app.add_subcommand("precompute", "Ray-trace the light transport of a scene");
  sub->add_option("--scene", args->scene, "Built-in scene name or scene JSON file")->required();
  sub->add_option("--out", args->out, "Transport file to write (HDF5)")->required();
  sub->add_option("--size", args->size, "Image size WxH (default: the scene's)");
  sub->add_option("--camera", args->camera,
                  "auto: frame the scene's bounds from its camera's direction; auto:THETA,PHI: "
                  "from that direction (degrees: THETA from +Y, PHI from -Z towards +X)");
  sub->add_option("--cubemap", args->cubemap, "Cube-map face resolution R (6 R^2 directions)");
  sub->add_option("--spp", args->spp,
                  "Camera samples per pixel (default 4): anti-aliased silhouettes and textures");
  sub->add_option("--aa", args->antialiasing,
                  "adaptive: trace every sample only where they see different surfaces "
                  "(default); full: everywhere, shadow edges too, at spp times the cost");
  sub->add_option("--texel-rays", args->texelRays,
                  "Occlusion rays per texel (fractional visibility)");
  sub->add_option("--precision", args->precision, "Stored precision: f16 or f32");
  sub->add_option("--bounces", args->bounces,
                  "Interreflections: light that bounces up to K times off scene surfaces "
                  "(default 0: direct light)");
  sub->add_option("--indirect-samples", args->indirectSamples,
                  "Paths per traced camera sample for the bounced light (default 64): noise "
                  "falls as they rise");
  sub->add_option("--indirect-cache", args->indirectCache,
                  "Path vertices share the visibility of one point per cell of this size, a "
                  "fraction of the scene's extent (default 1/1024); 0 traces every vertex's own "
                  "shadow rays (unbiased, slow)");
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
