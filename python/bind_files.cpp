// The Python module's functions over image files: images read as numpy
// arrays, and their channels.
#include <pybind11/stl.h>

#include <memory>
#include <vector>

#include "core/error.h"
#include "imageio/image_file.h"
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

/// Module functions over image files: images and their channels.
void registerFiles(py::module_& m) {
  m.def("read_image", &readImage, py::arg("path"),
        "An image file (EXR, HDR, PNG, ...) as an H x W x C float32 array.");
  m.def("image_channel_names", &imageChannelNames, py::arg("path"),
        "The names of an image file's channels, in read_image's order (labels.exr: albedo.R, "
        "N.X, Z, ...).");
}

}  // namespace acpca::python
