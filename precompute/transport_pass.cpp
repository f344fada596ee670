#include "precompute/transport_pass.h"

#include <tbb/info.h>

namespace acpca {

namespace {

IndirectSettings indirectSettings(const Scene& scene, const PrecomputeOptions& o) {
  IndirectSettings s;
  s.bounces = o.bounces;
  s.samples = o.indirectSamples;
  s.cacheCell = o.indirectCacheCell;
  s.channels = sceneIsGrey(scene) ? 1 : 3;
  return s;
}

}  // namespace

void validatePrecomputeOptions(const PrecomputeOptions& o) {
  if (o.cubemapResolution < 1 || o.cubemapResolution > 256)
    throw ParameterError("cube-map resolution", o.cubemapResolution, "is out of range 1..256");
  if (o.samplesPerPixel < 1 || o.samplesPerPixel > 256)
    throw ParameterError("samples per pixel", o.samplesPerPixel, "is out of range 1..256");
  if (o.texelRays < 1 || o.texelRays > 1024)
    throw ParameterError("rays per texel", o.texelRays, "is out of range 1..1024");
  if (o.threads < 0) throw ParameterError("threads", o.threads, "must be >= 0");
  if (o.bounces < 0 || o.bounces > kMaxBounces)
    throw ParameterError("bounces", o.bounces, concat("is out of range 0..", kMaxBounces));
  if (o.indirectSamples < 1 || o.indirectSamples > kMaxIndirectSamples)
    throw ParameterError("indirect samples", o.indirectSamples,
                         concat("is out of range 1..", kMaxIndirectSamples));
  if (!(o.indirectCacheCell >= 0 && o.indirectCacheCell <= 0.1))
    throw ParameterError("indirect cache cell", o.indirectCacheCell,
                         "is out of range 0..0.1 (a fraction of the scene's extent; 0: no cache)");
}

int arenaThreads(int threads) {
  return threads > 0 ? threads : tbb::info::default_concurrency();
}

TransportPass::TransportPass(const Scene& scene, const PrecomputeOptions& options)
    : lattice(options.cubemapResolution),
      embree(scene),
      gbuffer(renderGBuffer(embree, scene.camera, options.samplesPerPixel)),
      dirs(makeTexelDirections(lattice, options.texelRays)),
      shadows(embree, dirs, lattice),
      indirect(options.bounces > 0
                   ? std::make_unique<IndirectLight>(embree, shadows, lattice.size(), scene,
                                                     indirectSettings(scene, options))
                   : nullptr),
      renderer(gbuffer, shadows, lattice, options.antialiasing, indirect.get()) {}

namespace {

/// A row's traced samples (sampleWeights: those of weight > 0), appended to
/// the lamp geometry: what the row's direct light came from.
void appendLampSamples(const GBuffer& gbuffer, int x, int y, Antialiasing mode,
                       LampGeometry& lamps) {
  thread_local std::vector<float> weights;
  sampleWeights(gbuffer, x, y, mode, weights);
  for (int s = 0; s < gbuffer.samplesPerPixel; ++s) {
    if (weights[s] <= 0) continue;
    const PixelSample& ps = gbuffer.at(x, y, s);
    lamps.origin.insert(lamps.origin.end(), ps.origin.data(), ps.origin.data() + 3);
    lamps.normal.insert(lamps.normal.end(), ps.normal.data(), ps.normal.data() + 3);
    lamps.geometricNormal.insert(lamps.geometricNormal.end(), ps.geometricNormal.data(),
                                 ps.geometricNormal.data() + 3);
    lamps.tangent.insert(lamps.tangent.end(), ps.tangent.data(), ps.tangent.data() + 3);
    lamps.weight.push_back(weights[s]);
    lamps.material.push_back(ps.material);
  }
  lamps.sampleStart.push_back(lamps.samples());
}

}  // namespace

TransportHeader transportHeader(const Scene& scene, const PrecomputeOptions& options,
                                const TransportPass& pass) {
  const GBuffer& gbuffer = pass.gbuffer;
  const int channels = pass.channels();
  TransportHeader header;
  pass.embree.describeSurfaces(header.lamps);
  header.lamps.sampleStart = {0};
  header.camera = scene.camera;
  header.cubemapResolution = options.cubemapResolution;
  header.samplesPerPixel = options.samplesPerPixel;
  header.texelRays = options.texelRays;
  header.precision = options.precision;
  header.scene = scene.name;
  header.channels = channels;
  if (options.bounces > 0) {
    header.bounces = options.bounces;
    header.indirectSamples = options.indirectSamples;
    header.indirectCacheCell = options.indirectCacheCell;
  }
  header.objectNames = scene.objectNames();
  const ImageSize size = scene.camera.size;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      Eigen::Vector3f albedo = Eigen::Vector3f::Zero();
      int hits = 0, first = -1;
      for (int s = 0; s < options.samplesPerPixel; ++s) {
        const PixelSample& ps = gbuffer.at(x, y, s);
        if (ps.material < 0) continue;
        albedo += ps.albedo;
        if (hits++ == 0) first = s;
      }
      if (hits == 0) continue;
      header.pixels.push_back(y * size.width + x);
      albedo /= float(hits);
      header.albedo.insert(header.albedo.end(), albedo.data(), albedo.data() + 3);
      header.coverage.push_back(float(hits) / options.samplesPerPixel);
      const PixelSample& firstHit = gbuffer.at(x, y, first);
      header.normals.insert(header.normals.end(), firstHit.normal.data(),
                            firstHit.normal.data() + 3);
      header.positions.insert(header.positions.end(), firstHit.origin.data(),
                              firstHit.origin.data() + 3);
      header.objects.push_back(firstHit.material);  // the ray tracer's geometry id
      appendLampSamples(gbuffer, x, y, options.antialiasing, header.lamps);
    }
  return header;
}

}  // namespace acpca
