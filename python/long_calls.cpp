// precompute and compress from Python, with the CLI's options, a progress
// callback, the GIL released and Ctrl-C honoured (interruptible.h).
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "cluster/compress.h"
#include "cluster/model_file.h"
#include "core/error.h"
#include "core/input_guard.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "python/interruptible.h"
#include "python/long_calls.h"
#include "python/opening_file.h"

namespace acpca::python {

namespace {

py::dict precompute(const std::string& scene, const std::string& out,
                    const std::optional<std::pair<int, int>>& size, const std::string& camera,
                    int cubemap, int spp, const std::string& aa, int texelRays,
                    const std::string& precision, int bounces, int indirectSamples,
                    double indirectCache, int threads, bool force, const py::object& progress) {
  PrecomputeOptions o;
  o.bounces = bounces;
  o.indirectSamples = indirectSamples;
  o.indirectCacheCell = indirectCache;
  o.cubemapResolution = cubemap;
  o.samplesPerPixel = spp;
  o.antialiasing = kAntialiasingNames.parse(aa);
  o.texelRays = texelRays;
  o.precision = parsePrecision(precision);
  o.threads = threads;
  o.force = force;
  PrecomputeStats stats;
  // A missing scene file is raised (with the GIL) as FileNotFoundError.
  openingFile(isBuiltinScene(scene) ? std::string() : scene, [&] {
    runInterruptible([&](WorkContext& context) {
      Scene s = loadScene(scene);
      if (size) s.camera.size = {size->first, size->second};
      applyCameraSpec(s, camera);
      s.validate();
      // Called from one thread between bands of rows: where a cancel lands.
      o.progress = [&](long long done, long long total) {
        context.check();
        if (!progress.is_none()) context.callPython([&] { progress(done, total); });
      };
      // The indirect cache's stages are cancel points too.
      o.cacheProgress = o.cacheFillProgress = [&](long long, long long) { context.check(); };
      stats = precomputeTransport(s, out, o);
    });
    return 0;
  });
  py::dict d;
  d["occupied_pixels"] = stats.occupiedPixels;
  d["occlusion_rays"] = stats.occlusionRays;
  d["seconds"] = stats.seconds;
  d["transport_seconds"] = stats.transportSeconds;
  d["rays_per_second"] = stats.raysPerSecond();
  d["supersampled_pixels"] = stats.supersampledPixels;
  d["bytes_written"] = stats.bytesWritten;
  d["channels"] = stats.channels;
  d["path_rays"] = stats.pathRays;
  d["cache_points"] = stats.cachePoints;
  d["cache_seconds"] = stats.cacheSeconds;
  return d;
}

py::dict compress(const std::string& transport, const std::string& out, const std::string& method,
                  double tolerance, double globalEnergy, int clusters, int block,
                  bool exactQuadTree, bool allocateRanks, const std::string& coeffs,
                  const std::string& bases, int sampleRows, std::uint64_t seed, bool force,
                  const py::object& progress) {
  CompressOptions o;
  o.method = parseMethod(method);
  o.tolerance = tolerance;
  o.globalEnergy = globalEnergy;
  o.clusters = clusters;
  o.block = block;
  o.exactQuadTree = exactQuadTree;
  o.allocateRanks = allocateRanks;
  o.coeffs = parseCoeffPrecision(coeffs);
  o.bases = parseBasisPrecision(bases);
  o.sampleRows = sampleRows;
  o.seed = seed;
  o.force = force;
  Model model;
  openingFile(transport, [&] {
    refuseOutputOverInputs(out, {transport});
    runInterruptible([&](WorkContext& context) {
      // Stage messages are where a cancel lands: compress checks between stages.
      o.log = [&](const std::string& message) {
        context.check();
        if (!progress.is_none()) context.callPython([&] { progress(message); });
      };
      const TransportReader reader(transport);
      model = compressTransport(reader, o);
      context.check();
      writeModel(model, out);
    });
    return 0;
  });
  py::dict d;
  d["method"] = model.method;
  d["clusters"] = model.clusters();
  d["global_bases"] = model.globalBases();
  d["cost_per_pixel"] = model.costPerPixel();
  d["transport_error"] = model.transportError;
  d["bytes_per_frame"] = model.frameBytes();
  d["seconds"] = model.compressSeconds;
  return d;
}

}  // namespace

void registerLongCalls(py::module_& m) {
  m.def("precompute", &precompute, py::arg("scene"), py::arg("out"), py::kw_only(),
        py::arg("size") = py::none(), py::arg("camera") = "", py::arg("cubemap") = 32,
        py::arg("spp") = kDefaultSamplesPerPixel, py::arg("aa") = "adaptive",
        py::arg("texel_rays") = 1, py::arg("precision") = "f16", py::arg("bounces") = 0,
        py::arg("indirect_samples") = kDefaultIndirectSamples,
        py::arg("indirect_cache") = kDefaultIndirectCacheCell, py::arg("threads") = 0,
        py::arg("force") = false, py::arg("progress") = py::none(),
        "Ray-trace a scene (built-in name or JSON file) into the transport file `out`, as "
        "`adaptive-cpca precompute`; size is (width, height); bounces > 0 adds interreflections. "
        "progress(done, total) is called between bands of rows. Ctrl-C stops it and leaves no "
        "file. An image whose transport would not fit the disk or memory is refused before "
        "any work unless force=True.");
  m.def("compress", &compress, py::arg("transport"), py::arg("out"), py::kw_only(),
        py::arg("method") = "adaptive-quad", py::arg("tolerance") = 0.999,
        py::arg("global_energy") = 0.999, py::arg("clusters") = 10, py::arg("block") = 0,
        py::arg("exact_quad_tree") = false, py::arg("allocate_ranks") = false,
        py::arg("coeffs") = "f32", py::arg("bases") = "f32", py::arg("sample_rows") = 16384,
        py::arg("seed") = 1, py::arg("force") = false, py::arg("progress") = py::none(),
        "Compress a transport into a model file, as `adaptive-cpca compress`; progress(message) "
        "is called at each stage, where Ctrl-C stops it (nothing is written).");
}

}  // namespace acpca::python
