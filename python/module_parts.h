#pragma once
// What the parts of the Python module share: the array types it takes, an
// environment and a lattice lighting as Python holds them, and each part's
// registration (python/adaptive_cpca.cpp makes the module from them).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "lighting/local_light.h"
#include "lighting/rotation.h"

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

/// An environment and the name it goes by.
struct PyEnvironment {
  std::shared_ptr<const Environment> env;
};

/// An environment integrated onto a lattice under a rotation (kept for the
/// background and for checks).
struct PyLighting {
  std::shared_ptr<const Environment> env;
  EnvRotation rotation;
  LatticeLighting values;
  std::string domain;  ///< what it was made for: "6x8x8", "331 lights"
};

/// A light built in code, checked as a parsed one is and named by its spec.
LocalLight madeLight(LocalLight light);

/// No environment: local lights alone, over black.
std::shared_ptr<const Environment> darkness();

/// adaptive_cpca.Environment and adaptive_cpca.Lighting (bind_lighting.cpp).
void registerEnvironments(py::module_& m);
/// Light, PointLight, SphereLight and SpotLight (bind_lighting.cpp).
void registerLights(py::module_& m);
/// read_image, draw_lightings, image_channel_names (bind_files.cpp).
void registerFiles(py::module_& m);
/// adaptive_cpca.Relighter and open (relighter.cpp).
void registerRelighter(py::module_& m);

}  // namespace acpca::python
