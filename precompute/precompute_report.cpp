#include "precompute/precompute_report.h"

#include <sstream>

#include "core/error.h"
#include "core/ranks.h"
#include "core/resources.h"
#include "core/text.h"

namespace acpca {

nlohmann::json toJson(const PrecomputeOptions& o) {
  return {{"cubemap", o.cubemapResolution},
          {"spp", o.samplesPerPixel},
          {"antialiasing", kAntialiasingNames.name(o.antialiasing)},
          {"texel_rays", o.texelRays},
          {"precision", precisionName(o.precision)},
          {"bounces", o.bounces},
          {"indirect_samples", o.indirectSamples},
          {"indirect_cache_cell", o.indirectCacheCell}};
}

nlohmann::json toJson(const PrecomputeStats& s) {
  return {{"triangles", s.triangles},
          {"degenerate_triangles", s.degenerateTriangles},
          {"occupied_pixels", s.occupiedPixels},
          {"occlusion_rays", s.occlusionRays},
          {"supersampled_pixels", s.supersampledPixels},
          {"rays_per_second", s.raysPerSecond()},
          {"transport_seconds", s.transportSeconds},
          {"seconds", s.seconds},
          {"threads_used", s.threadsUsed},
          {"row_bytes", s.bytesWritten},
          {"channels", s.channels},
          {"path_rays", s.pathRays},
          {"cache_points", s.cachePoints},
          {"cache_rays", s.cacheRays},
          {"cache_seconds", s.cacheSeconds}};
}

std::string describeInWords(const PrecomputeStats& stats, const PrecomputeOptions& options,
                            ImageSize size) {
  std::ostringstream out;
  out << size.width << "x" << size.height << ", " << stats.occupiedPixels << " occupied pixels, "
      << 6 * options.cubemapResolution * options.cubemapResolution << " directions, "
      << formatBytes(stats.bytesWritten) << " of rows; " << stats.occlusionRays
      << " occlusion rays in " << stats.transportSeconds << " s (" << stats.raysPerSecond() / 1e6
      << " M rays/s, " << stats.threadsUsed << " threads"
      << (ranks::distributed() ? concat(" over ", ranks::count(), " ranks") : std::string())
      << "), total " << stats.seconds << " s, peak memory " << formatBytes(peakMemoryBytes())
      << "; " << stats.supersampledPixels << " pixels traced at " << options.samplesPerPixel
      << " samples, the rest at 1\n";
  if (options.bounces > 0)
    out << "indirect light: " << options.bounces << " bounce(s), " << options.indirectSamples
        << " paths per traced sample, " << stats.pathRays << " path rays; "
        << (stats.channels == 3 ? "R, G and B rows (coloured surfaces)"
                                : "one row per pixel (grey surfaces)")
        << "; visibility cache: "
        << (options.indirectCacheCell > 0 ? concat(stats.cachePoints, " points, ", stats.cacheRays,
                                                   " rays, ", stats.cacheSeconds, " s")
                                          : std::string("off (exact shadow rays at every vertex)"))
        << "\n";
  if (stats.degenerateTriangles > 0)
    out << "note: " << stats.degenerateTriangles
        << " zero-area triangles were left out (they cover nothing)\n";
  return out.str();
}

}  // namespace acpca
