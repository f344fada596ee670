// The Python module's environments, lattice lightings and local lights.
#include <pybind11/stl.h>

#include <tuple>
#include <vector>

#include "core/error.h"
#include "lighting/local_light.h"
#include "lighting/spec_parsing.h"
#include "python/module_parts.h"
#include "python/opening_file.h"

namespace acpca::python {

namespace {

PyEnvironment environmentFromSpec(const std::string& spec) {
  // Without the GIL: a large map takes a while, and its warnings take the GIL.
  const bool analytic = isAnalyticEnvironment(spec);
  return openingFile(analytic ? std::string() : spec, [&] {
    py::gil_scoped_release release;
    return PyEnvironment{std::shared_ptr<const Environment>(loadEnvironment(spec)),
                         newSourceSplits()};
  });
}

PyEnvironment environmentFromArray(const FloatArray& array, const std::string& name) {
  if (array.ndim() != 3 && array.ndim() != 2)
    throw py::value_error("a lat-long array is H x W x 3 (or H x W for grey), float32");
  const int height = static_cast<int>(array.shape(0)), width = static_cast<int>(array.shape(1));
  const int channels = array.ndim() == 3 ? static_cast<int>(array.shape(2)) : 1;
  std::unique_ptr<Environment> env;
  {
    py::gil_scoped_release release;
    env = makeEnvironmentFromPixels(name, name, width, height, channels, array.data());
  }
  return {std::move(env), newSourceSplits()};
}

/// The map under each (yaw, pitch, roll) on a 6 x R x R lattice, B x l x 3:
/// adaptive_cpca.torch's fast path on the CPU (the same integration).
py::array_t<double> latticeLightings(const PyEnvironment& e, int cubemap,
                                     const std::vector<std::tuple<double, double, double>>& turns) {
  const CubeLattice lattice(cubemap);
  const auto count = static_cast<py::ssize_t>(turns.size());
  py::array_t<double> out({count, static_cast<py::ssize_t>(lattice.size()), py::ssize_t{3}});
  double* values = out.mutable_data();
  py::gil_scoped_release release;
  for (size_t k = 0; k < turns.size(); ++k) {
    const EnvRotation rotation{std::get<0>(turns[k]), std::get<1>(turns[k]), std::get<2>(turns[k])};
    validateRotation(rotation);
    const LatticeLighting lighting = computeLighting(*e.env, lattice, rotation);
    std::copy(lighting.begin(), lighting.end(), values + k * lighting.size());
  }
  return out;
}

}  // namespace

std::shared_ptr<const Environment> darkness() {
  static const std::shared_ptr<const Environment> black = makeConstantEnvironment(Rgb::Zero());
  return black;
}

namespace {

/// An emission given as one number (grey) or three (R, G, B).
using Emission = std::variant<double, std::tuple<double, double, double>>;
Rgb emissionOf(const Emission& e) {
  if (const double* v = std::get_if<double>(&e)) return Rgb::Constant(*v);
  const auto& [r, g, b] = std::get<std::tuple<double, double, double>>(e);
  return {r, g, b};
}
using Point3 = std::tuple<double, double, double>;
Vec3 vecOf(const Point3& p) {
  return {std::get<0>(p), std::get<1>(p), std::get<2>(p)};
}

}  // namespace

LocalLight madeLight(LocalLight light) {
  validateLocalLight(light);
  light.spec = light.canonicalSpec();
  return light;
}

std::vector<std::vector<LocalLight>> lightSetsAlong(const std::vector<LocalLight>& lights,
                                                    const std::optional<DoubleArray>& positions) {
  if (!positions) return {lights};
  const DoubleArray& p = *positions;
  if (p.ndim() != 3 || p.shape(1) != static_cast<py::ssize_t>(lights.size()) || p.shape(2) != 3)
    throw py::value_error(concat("light_positions must be F x ", lights.size(),
                                 " x 3: a position for each of the lights in each frame"));
  std::vector<std::vector<LocalLight>> sets;
  for (py::ssize_t f = 0; f < p.shape(0); ++f) {
    std::vector<LocalLight> set = lights;
    for (size_t k = 0; k < set.size(); ++k) {
      set[k].position = Vec3(p.at(f, k, 0), p.at(f, k, 1), p.at(f, k, 2));
      set[k].spec.clear();
      set[k] = madeLight(set[k]);
    }
    sets.push_back(std::move(set));
  }
  if (sets.empty()) throw py::value_error("light_positions holds no frames");
  return sets;
}

void registerEnvironments(py::module_& m) {
  py::class_<PyEnvironment>(m, "Environment",
                            "A lighting: a built-in map, an image file or a numpy array.")
      .def(py::init(&environmentFromSpec), py::arg("spec"),
           (environmentGrammarList() +
            ", or an image file (lat-long .exr/.hdr, or a 4:3 cube cross)")
               .c_str())
      .def_static("from_array", &environmentFromArray, py::arg("array"), py::arg("name") = "array",
                  "A lat-long map, H x 2H x 3 (row 0 at the zenith), checked as a file is.")
      .def_property_readonly("name", [](const PyEnvironment& e) { return e.env->name(); })
      .def("lattice_lightings", &latticeLightings, py::arg("cubemap"), py::arg("rotations"),
           "Each (yaw, pitch, roll)'s lighting on a 6 x R x R lattice, B x l x 3, as "
           "Relighter.lighting(...).values gives it for a file of that lattice.")
      .def("__repr__", [](const PyEnvironment& e) {
        return "<adaptive_cpca.Environment " + e.env->name() + ">";
      });

  py::class_<PyLighting>(m, "Lighting",
                         "An environment under a rotation, integrated onto a lattice "
                         "(Relighter.lighting).")
      .def_property_readonly("energy",
                             [](const PyLighting& l) {
                               const Rgb e = totalEnergy(l.values);
                               return std::make_tuple(e[0], e[1], e[2]);
                             })
      .def_property_readonly(
          "values",
          [](const PyLighting& l) {
            py::array_t<double> out(
                {static_cast<py::ssize_t>(l.values.size() / 3), static_cast<py::ssize_t>(3)});
            std::copy(l.values.begin(), l.values.end(), out.mutable_data());
            return out;
          },
          "Per column (texel, or a captured set's light) its RGB lighting: radiance "
          "integrated over the texel or the light's cell, l x 3.")
      .def_property_readonly(
          "domain", [](const PyLighting& l) { return l.domain; },
          "What it was made for: '6x32x32', or '331 lights'.");
}

/// Light, PointLight, SphereLight and SpotLight: local lights (docs/lighting.md).
void registerLights(py::module_& m) {
  py::class_<LocalLight>(m, "Light",
                         "A local light: point, sphere or spot (docs/lighting.md, \"Local "
                         "lights\"), from the CLI's spec or PointLight, SphereLight, SpotLight.")
      .def(py::init(&parseLocalLight), py::arg("spec"),
           ("A light from its spec:\n" + lightGrammarLines()).c_str())
      .def_property_readonly("spec", &LocalLight::canonicalSpec)
      .def_property_readonly("kind", [](const LocalLight& l) { return std::string(l.kindName()); })
      .def_property_readonly("position",
                             [](const LocalLight& l) {
                               return Point3{l.position.x(), l.position.y(), l.position.z()};
                             })
      .def("__repr__",
           [](const LocalLight& l) { return "<adaptive_cpca.Light " + l.canonicalSpec() + ">"; });
  m.def(
      "PointLight",
      [](const Point3& position, const Emission& intensity) {
        LocalLight l;
        l.position = vecOf(position);
        l.emission = emissionOf(intensity);
        return madeLight(l);
      },
      py::arg("position"), py::arg("intensity"),
      "A point light of radiant intensity I (grey, or (R, G, B)) at a world position.");
  m.def(
      "SphereLight",
      [](const Point3& position, double radius, const Emission& radiance) {
        LocalLight l;
        l.shape = SphereLight{radius};
        l.position = vecOf(position);
        l.emission = emissionOf(radiance);
        return madeLight(l);
      },
      py::arg("position"), py::arg("radius"), py::arg("radiance"),
      "A sphere of uniform radiance L (grey, or (R, G, B)).");
  m.def(
      "SpotLight",
      [](const Point3& position, const Point3& direction, double halfAngle,
         const Emission& intensity) {
        LocalLight l;
        l.shape = SpotLight{vecOf(direction), halfAngle};
        l.position = vecOf(position);
        l.emission = emissionOf(intensity);
        return madeLight(l);
      },
      py::arg("position"), py::arg("direction"), py::arg("half_angle"), py::arg("intensity"),
      "A point light inside a cone of half_angle degrees around direction.");
}

}  // namespace acpca::python
