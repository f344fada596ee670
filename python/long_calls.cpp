// precompute, compress and import from Python, with the CLI's options, a progress
// callback, the GIL released and Ctrl-C honoured (interruptible.h).
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>
#include <string>

#include <pybind11/numpy.h>

#include "capture/lights_file.h"
#include "capture/olat_import.h"
#include "cluster/compress.h"
#include "core/error.h"
#include "core/input_guard.h"
#include "model/model_file.h"
#include "precompute/precompute_report.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "python/interruptible.h"
#include "python/long_calls.h"
#include "python/opening_file.h"
#include "python/to_python.h"

namespace acpca::python {

namespace {

namespace fs = std::filesystem;

py::object precompute(const std::string& scene, const std::string& out,
                      const std::optional<std::pair<int, int>>& size, const std::string& camera,
                      int cubemap, int spp, const std::string& aa, int texelRays,
                      const std::string& precision, int bounces, int indirectSamples,
                      double indirectCache, int threads, bool force, std::optional<int> view,
                      const py::object& progress) {
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
      // A scene of several views: one view per call (the CLI writes them all).
      const int views = static_cast<int>(s.viewCount());
      if (view && (*view < 0 || *view >= views))
        throw ParameterError("view", *view, concat("is not one of the scene's 0..", views - 1));
      if (!view && views > 1)
        throw ParameterError("view", "None",
                             concat("the scene has ", views, " views: give view=0..", views - 1));
      s = s.view(view.value_or(0));
      if (size) s.camera.size = {size->first, size->second};
      applyCameraSpec(s, camera);
      s.validate();
      // Called from one thread between image rows: where a cancel lands.
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
  return toPython(toJson(stats));
}

py::object compress(const std::string& transport, const std::string& out, const std::string& method,
                    double tolerance, double globalEnergy, int clusters, int block,
                    bool exactQuadTree, bool allocateRanks, const std::string& coeffs,
                    const std::string& bases, int sampleRows, int clusteringDims,
                    std::uint64_t seed, bool force, const py::object& progress) {
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
  o.clusteringDims = clusteringDims;
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
  return toPython(summaryJson(model));
}

using FloatImages = py::array_t<float, py::array::c_style | py::array::forcecast>;
using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// Rows of an (N, 3) array as vectors, N = `count`; `name` in errors.
std::vector<Eigen::Vector3d> vectorsOf(const Doubles& a, size_t count, const std::string& name) {
  if (a.ndim() != 2 || a.shape(1) != 3 || static_cast<size_t>(a.shape(0)) != count)
    throw ParameterError(name, concat(a.ndim(), "-d array"),
                         concat("must be ", count, " x 3 (one row per image)"));
  std::vector<Eigen::Vector3d> v;
  for (size_t k = 0; k < count; ++k) v.emplace_back(a.at(k, 0), a.at(k, 1), a.at(k, 2));
  return v;
}

py::object importTransport(const py::object& images, const Doubles& directions,
                           const std::string& out, const std::optional<Doubles>& intensities,
                           const std::optional<std::string>& mask, double cellCap,
                           const std::string& precision, const std::string& encoding, bool force,
                           const py::object& progress) {
  OlatImportOptions o;
  o.out = out;
  o.mask = mask.value_or("");
  o.precision = parsePrecision(precision);
  o.capDegrees = cellCap;
  o.force = force;
  o.name = fs::path(out).stem().string();
  const TransferFunction decoding = kTransferFunctionNames.parse(encoding);
  // The images: paths, or an (N, H, W, 3) array of linear values.
  std::optional<FloatImages> pixels;
  std::vector<std::string> paths;
  if (py::isinstance<py::array>(images)) {
    pixels = images.cast<FloatImages>();
    if (pixels->ndim() != 4 || pixels->shape(3) != 3 || pixels->shape(0) < 1)
      throw ParameterError("images", concat(pixels->ndim(), "-d array"),
                           "must be N x H x W x 3 (linear RGB)");
  } else {
    paths = images.cast<std::vector<std::string>>();
    if (paths.empty()) throw ParameterError("images", "[]", "give one image per light");
  }
  const size_t count = pixels ? static_cast<size_t>(pixels->shape(0)) : paths.size();
  requireLightCount(count, "images");
  OlatLights lights;
  for (const Eigen::Vector3d& d : vectorsOf(directions, count, "directions")) {
    if (!(d.norm() > 0) || !d.allFinite())
      throw ParameterError("directions", concat(d.transpose()), "a direction must not be zero");
    lights.directions.push_back(d.normalized());
  }
  lights.irradiance = intensities ? vectorsOf(*intensities, count, "intensities")
                                  : std::vector<Eigen::Vector3d>(count, Eigen::Vector3d::Ones());
  OlatImportResult result;
  openingFile(paths.empty() ? o.mask : paths.front(), [&] {
    std::vector<std::string> inputs = paths;
    if (!o.mask.empty()) inputs.push_back(o.mask);
    refuseOutputOverInputs(out, inputs);
    runInterruptible([&](WorkContext& context) {
      o.progress = [&](long long done, long long total) {
        context.check();
        if (!progress.is_none()) context.callPython([&] { progress(done, total); });
      };
      const auto source = pixels ? imagesInMemory(pixels->data(), static_cast<int>(count),
                                                  {static_cast<int>(pixels->shape(2)),
                                                   static_cast<int>(pixels->shape(1))})
                                 : openImageFiles(paths, decoding);
      result = importOlat(*source, lights, o);
    });
    return 0;
  });
  return toPython(importReport(result, out));
}

}  // namespace

void registerLongCalls(py::module_& m) {
  m.def(
      "linear_algebra", [] { return toPython(linearAlgebraJson()); },
      "The linear algebra this process runs: blas_core (OpenBLAS's kernels), "
      "blas_core_chosen_by and eigensolver (as compress --json reports them).");
  // The defaults are the library's, as the CLI's are.
  const PrecomputeOptions render;
  m.def("precompute", &precompute, py::arg("scene"), py::arg("out"), py::kw_only(),
        py::arg("size") = py::none(), py::arg("camera") = "",
        py::arg("cubemap") = render.cubemapResolution, py::arg("spp") = render.samplesPerPixel,
        py::arg("aa") = kAntialiasingNames.name(render.antialiasing),
        py::arg("texel_rays") = render.texelRays,
        py::arg("precision") = precisionName(render.precision), py::arg("bounces") = render.bounces,
        py::arg("indirect_samples") = render.indirectSamples,
        py::arg("indirect_cache") = render.indirectCacheCell, py::arg("threads") = render.threads,
        py::arg("force") = render.force, py::arg("view") = py::none(),
        py::arg("progress") = py::none(),
        "Ray-trace a scene (built-in name or JSON file) into the transport file `out`, as "
        "`adaptive-cpca precompute`; size is (width, height); bounces > 0 adds interreflections. "
        "progress(done, total) is called between image rows. Ctrl-C stops it and leaves no "
        "file. An image whose transport would not fit the disk or memory is refused before "
        "any work unless force=True. A scene file of several cameras needs view=K: that view "
        "alone (the CLI's STEM_vK). Returns the figures `precompute --json` reports.");
  const CompressOptions c;
  m.def("compress", &compress, py::arg("transport"), py::arg("out"), py::kw_only(),
        py::arg("method") = methodName(c.method), py::arg("tolerance") = c.tolerance,
        py::arg("global_energy") = c.globalEnergy, py::arg("clusters") = c.clusters,
        py::arg("block") = c.block, py::arg("exact_quad_tree") = c.exactQuadTree,
        py::arg("allocate_ranks") = c.allocateRanks,
        py::arg("coeffs") = coeffPrecisionName(c.coeffs),
        py::arg("bases") = coeffPrecisionName(c.bases), py::arg("sample_rows") = c.sampleRows,
        py::arg("clustering_dims") = c.clusteringDims, py::arg("seed") = c.seed,
        py::arg("force") = c.force, py::arg("progress") = py::none(),
        "Compress a transport into a model file, as `adaptive-cpca compress`; progress(message) "
        "is called at each stage, where Ctrl-C stops it (nothing is written).");
  m.def(
      "import_transport", &importTransport, py::arg("images"), py::arg("directions"), py::kw_only(),
      py::arg("out"), py::arg("intensities") = py::none(), py::arg("mask") = py::none(),
      py::arg("cell_cap") = 0.0, py::arg("precision") = "f16", py::arg("encoding") = "auto",
      py::arg("force") = false, py::arg("progress") = py::none(),
      "A captured one-light-at-a-time set into the transport file `out`, as `adaptive-cpca "
      "import`: images an (N, H, W, 3) float array of linear values or N image paths "
      "(encoding 'auto': 8/16-bit ones sRGB-decoded; 'linear'; 'srgb'), directions (N, 3) "
      "from the subject toward each light, intensities (N, 3) the irradiance each "
      "delivered (default 1), mask an image path (default: pixels black in every image are "
      "background), cell_cap the cells' cap in degrees (0: the default). A set whose rows "
      "may not fit memory or the disk is refused before any work unless force=True. progress(done, "
      "total) is called per band of image rows. Returns what `import --json` reports.");
}

}  // namespace acpca::python
