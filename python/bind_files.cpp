// The Python module's functions over files and draws: images read as numpy
// arrays, their channels, and the lightings a sampled batch relights.
#include <pybind11/stl.h>

#include <cstdint>
#include <memory>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "imageio/image_file.h"
#include "lighting/lighting_sampler.h"
#include "python/module_parts.h"
#include "python/opening_file.h"

namespace acpca::python {

namespace {

std::unique_ptr<ImageReader> openImageFile(const std::string& path) {
  return openingFile(path, [&] {
    std::string error;
    auto opened = openImage(path, error);
    if (!opened) throw UserError(concat(path, ": cannot read the image: ", error));
    return opened;
  });
}

py::array_t<float> readImage(const std::string& path) {
  auto in = openImageFile(path);
  const ImageHeader spec = in->header();
  py::array_t<float> out({spec.height, spec.width, spec.channels});
  bool ok;
  {
    py::gil_scoped_release release;
    ok = in->readImage(0, spec.channels, PixelType::Float, out.mutable_data());
  }
  if (!ok) throw UserError(concat(path, ": cannot read the image pixels: ", in->error()));
  return out;
}

std::vector<std::string> imageChannelNames(const std::string& path) {
  return openImageFile(path)->header().channelNames;
}

}  // namespace

/// Module functions over files and draws: images, their channels, and the
/// lightings a sampled batch relights.
void registerFiles(py::module_& m) {
  m.def("read_image", &readImage, py::arg("path"),
        "An image file (EXR, HDR, PNG, ...) as an H x W x C float32 array.");
  m.def(
      "draw_lightings",
      [](size_t maps, int count, std::uint64_t seed, const std::string& rotation,
         double exposureJitter) {
        if (maps < 1) throw ParameterError("maps", maps, "give at least one map to draw from");
        LightingSampling s{count, seed, kSampledRotationNames.parse(rotation), exposureJitter};
        std::vector<std::tuple<size_t, double, double, double, double>> draws;
        for (const LightingDraw& d : drawLightings(s, maps))
          draws.emplace_back(d.map, d.rotation.yaw, d.rotation.pitch, d.rotation.roll,
                             d.exposureOffset);
        return draws;
      },
      py::arg("maps"), py::arg("count"), py::kw_only(), py::arg("seed") = 0,
      py::arg("rotation") = "yaw", py::arg("exposure_jitter") = 0.0,
      "The CLI's --env-sample draws: count tuples (map index, yaw, pitch, roll, exposure "
      "offset) from `maps` maps, the same for the same seed everywhere.");
  m.def("image_channel_names", &imageChannelNames, py::arg("path"),
        "The names of an image file's channels, in read_image's order (labels.exr: albedo.R, "
        "N.X, Z, ...).");
}

}  // namespace acpca::python
