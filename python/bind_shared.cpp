// What the package's pure-Python side takes from the compiled part where it
// loads, so that there is one implementation: the `--env-sample` draws, the
// cube lattice's texels and the SH means of its texels. None starts a thread,
// so a forked DataLoader worker calls them too, and its frames are the main
// process's to the bit. The pure-Python
// copies (adaptive_cpca.sampling, adaptive_cpca.torch.lattice and .domain)
// serve machines where the module does not load; tests hold them equal.
#include <pybind11/stl.h>

#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "lighting/lighting_sampler.h"
#include "lighting/sh_lighting.h"
#include "python/module_parts.h"
#include "transport/cube_lattice.h"

namespace acpca::python {

namespace {

using DrawTuple = std::tuple<size_t, double, double, double, double>;

DrawTuple drawTuple(const LightingDraw& d) {
  return {d.map, d.rotation.yaw, d.rotation.pitch, d.rotation.roll, d.exposureOffset};
}

LightingSampling samplingOf(size_t maps, int count, std::uint64_t seed, const std::string& rotation,
                            double exposureJitter) {
  if (maps < 1) throw ParameterError("maps", maps, "give at least one map to draw from");
  return {count, seed, kSampledRotationNames.parse(rotation), exposureJitter};
}

/// Directions [l, 3] and exact solid angles [l] of the 6 x R x R lattice.
std::tuple<py::array_t<double>, py::array_t<double>> cubeLattice(int resolution) {
  const CubeLattice lattice(resolution);
  const auto size = static_cast<py::ssize_t>(lattice.size());
  py::array_t<double> directions({size, py::ssize_t{3}}), solidAngles(size);
  auto d = directions.mutable_unchecked<2>();
  auto w = solidAngles.mutable_unchecked<1>();
  for (int j = 0; j < lattice.size(); ++j) {
    for (int a = 0; a < 3; ++a) d(j, a) = lattice.direction(j)[a];
    w(j) = lattice.solidAngle(j);
  }
  return {directions, solidAngles};
}

/// Per texel the mean of each realSh9 band over it [l, 9] (ShProjector's),
/// on the calling thread: a DataLoader worker, forked, may call it.
py::array_t<double> texelMeans(int resolution) {
  const CubeLattice lattice(resolution);
  std::vector<std::array<double, 9>> means;
  {
    py::gil_scoped_release release;
    means = texelSh9Means(lattice, false);
  }
  py::array_t<double> out({static_cast<py::ssize_t>(means.size()), py::ssize_t{9}});
  auto o = out.mutable_unchecked<2>();
  for (size_t j = 0; j < means.size(); ++j)
    for (int b = 0; b < 9; ++b) o(static_cast<py::ssize_t>(j), b) = means[j][b];
  return out;
}

}  // namespace

void registerShared(py::module_& m) {
  m.def(
      "draw_lightings",
      [](size_t maps, int count, std::uint64_t seed, const std::string& rotation,
         double exposureJitter) {
        const LightingSampling s = samplingOf(maps, count, seed, rotation, exposureJitter);
        std::vector<DrawTuple> draws;
        for (const LightingDraw& d : drawLightings(s, maps)) draws.push_back(drawTuple(d));
        return draws;
      },
      py::arg("maps"), py::arg("count"), py::kw_only(), py::arg("seed") = 0,
      py::arg("rotation") = "yaw", py::arg("exposure_jitter") = 0.0,
      "The CLI's --env-sample draws: count tuples (map index, yaw, pitch, roll, exposure "
      "offset) from `maps` maps, the same for the same seed everywhere.");
  m.def(
      "draw_lighting",
      [](std::uint64_t index, size_t maps, std::uint64_t seed, const std::string& rotation,
         double exposureJitter) {
        LightingSampling s = samplingOf(maps, 1, seed, rotation, exposureJitter);
        validateLightingSampling(s);
        return drawTuple(drawLightingAt(s, maps, index));
      },
      py::arg("index"), py::arg("maps"), py::kw_only(), py::arg("seed") = 0,
      py::arg("rotation") = "yaw", py::arg("exposure_jitter") = 0.0,
      "Draw `index` of draw_lightings' stream, made without the draws before it.");
  m.def("cube_lattice", &cubeLattice, py::arg("resolution"),
        "The 6 x R x R lattice's texel directions [l, 3] and exact solid angles [l] (float64).");
  m.def("texel_sh9_means", &texelMeans, py::arg("resolution"),
        "Per texel of the 6 x R x R lattice the mean of each of the nine real SH bands over it "
        "[l, 9] (float64), as the batch manifest's sh9 labels project lightings.");
}

}  // namespace acpca::python
