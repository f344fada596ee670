#pragma once
// What the parts of the Python module share: the array types it takes, an
// environment and a lattice lighting as Python holds them, and each part's
// registration (python/adaptive_cpca.cpp makes the module from them).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "lighting/local_light.h"
#include "lighting/map_sources.h"
#include "lighting/rotation.h"
#include "transport/transport_file.h"

namespace acpca::python {

namespace py = pybind11;

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using OutArray = py::array_t<float, py::array::c_style>;
/// What a caller passes as out=: taken as it is (never converted to a copy),
/// then checked.
using OutArgument = std::optional<py::array>;
/// A rank limit as Python gives it: None, a rank (int), a fraction (float) or
/// the CLI's text ("50%").
using PyRankLimit = std::optional<std::variant<int, double, std::string>>;

/// A map's sources split off under one finding, made on first use and
/// shared by the copies of a PyEnvironment (map_suns.cpp).
struct SourceSplits;

/// An environment and the name it goes by.
struct PyEnvironment {
  std::shared_ptr<const Environment> env;
  /// Shared by its copies (a list passed to relight_batch is copied); null
  /// for darkness, which has no sources.
  std::shared_ptr<SourceSplits> splits;
};
std::shared_ptr<SourceSplits> newSourceSplits();

/// `sun=` as Python gives it: "auto", "off", or K (an int, or its text), as
/// relight --sun.
using PySun = std::variant<int, std::string>;

/// An environment integrated onto a lattice under a rotation (kept for the
/// background and for checks).
struct PyLighting {
  std::shared_ptr<const Environment> env;
  EnvRotation rotation;
  LatticeLighting values;
  std::string domain;  ///< what it was made for: "6x8x8", "331 lights"
  /// The map's sources lit exactly, turned with it; the values hold the rest.
  std::vector<MapSource> sources;
};

/// What a frame of `env` integrates onto the lattice, and (into `sources`,
/// unturned) the sources split off to be lit exactly: the map less its
/// sources where `sun` finds some and the file can light them exactly, else
/// the whole map and none. Where it cannot, `warnOnce` is called (the sources
/// go through the lattice, as relight warns).
const Environment& latticePartOf(const PyEnvironment& env, const PySun& sun, bool exactLamps,
                                 const std::string& unavailable,
                                 const std::function<void()>& warnOnce,
                                 std::vector<MapSource>& sources);

/// A light built in code, checked as a parsed one is and named by its spec.
LocalLight madeLight(LocalLight light);

/// A batch's light sets: the lights as given, or, with positions (F x K x 3
/// for K lights), F sets of those lights moved to each row's positions.
std::vector<std::vector<LocalLight>> lightSetsAlong(const std::vector<LocalLight>& lights,
                                                    const std::optional<DoubleArray>& positions);

/// No environment: local lights alone, over black.
std::shared_ptr<const Environment> darkness();

/// A file's per-pixel queries (view_queries.cpp): the coverage of every
/// pixel, H x W (0 for background); the view's labels by AOV name (H x W (x
/// C) float32, object int32: what `relight --aov ... --label-format npy`
/// writes); and the shading of a frame relit over a black or transparent
/// background, frame / albedo label (0 where the albedo is 0), H x W x 3, as
/// the CLI's FRAME_shading files hold it.
py::array_t<float> coverageImage(const TransportHeader& header);
py::dict labelArrays(const TransportHeader& header, const std::string& path, bool model,
                     const std::string& aovs);
py::array_t<float> frameShadingArray(const TransportHeader& header,
                                     const py::array_t<float, py::array::c_style>& frame,
                                     bool keepNegative);

/// adaptive_cpca.Environment and adaptive_cpca.Lighting (bind_lighting.cpp).
void registerEnvironments(py::module_& m);
/// Light, PointLight, SphereLight and SpotLight (bind_lighting.cpp).
void registerLights(py::module_& m);
/// read_image, image_channel_names (bind_files.cpp).
void registerFiles(py::module_& m);
/// draw_lightings, draw_lighting, cube_lattice, texel_sh9_means: what the
/// pure-Python side takes from here where the module loads (bind_shared.cpp).
void registerShared(py::module_& m);
/// adaptive_cpca.Relighter and open (relighter.cpp).
void registerRelighter(py::module_& m);

}  // namespace acpca::python
