#include "precompute/precompute_json.h"

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

}  // namespace acpca
