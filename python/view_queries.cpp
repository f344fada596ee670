// A file's per-pixel queries for the Python relighter: coverage, the view's
// labels by AOV name, and a frame's shading, as the CLI writes them.
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/error.h"
#include "dataset/pixel_labels.h"
#include "python/module_parts.h"

namespace acpca::python {

/// Coverage of every pixel, H x W (0 for background).
py::array_t<float> coverageImage(const TransportHeader& header) {
  py::array_t<float> out({header.camera.size.height, header.camera.size.width});
  float* p = out.mutable_data();
  std::fill(p, p + out.size(), 0.0f);
  for (long long r = 0; r < header.rows(); ++r) p[header.pixels[r]] = header.coverage[r];
  return out;
}

/// The view's per-pixel labels by AOV name: H x W (x C) float32, object
/// int32; the very values `relight --aov ... --label-format npy` writes.
py::dict labelArrays(const TransportHeader& header, const std::string& path, bool model,
                     const std::string& aovs) {
  const std::vector<Aov> chosen = parseAovList(aovs);
  requireAovs(header, chosen, path, model);
  py::dict out;
  for (const LabelLayer& layer : viewLabels(header, chosen)) {
    std::vector<py::ssize_t> shape{header.camera.size.height, header.camera.size.width};
    if (layer.channels.size() > 1) shape.push_back(static_cast<py::ssize_t>(layer.channels.size()));
    if (layer.aov == Aov::Object) {
      py::array_t<std::int32_t> ids(shape);
      std::copy(layer.values.begin(), layer.values.end(), ids.mutable_data());
      out[kAovNames.name(layer.aov)] = ids;
    } else {
      py::array_t<float> values(shape);
      std::copy(layer.values.begin(), layer.values.end(), values.mutable_data());
      out[kAovNames.name(layer.aov)] = values;
    }
  }
  return out;
}

/// The shading of a frame relit over a black or transparent background:
/// frame / albedo label, 0 where the albedo is 0 (H x W x 3), as the CLI's
/// FRAME_shading files hold it.
py::array_t<float> frameShadingArray(const TransportHeader& header,
                                     const py::array_t<float, py::array::c_style>& frame,
                                     bool keepNegative) {
  const int height = header.camera.size.height, width = header.camera.size.width;
  const py::ssize_t channels = frame.ndim() == 3 ? frame.shape(2) : 0;
  if (frame.ndim() != 3 || frame.shape(0) != height || frame.shape(1) != width ||
      (channels != 3 && channels != 4))
    throw ParameterError("frame", concat(frame.ndim(), " dimensions"),
                         concat("is not ", height, " x ", width, " x 3 or 4"));
  py::array_t<float> out(std::vector<py::ssize_t>{height, width, 3});
  const std::vector<float> background(static_cast<size_t>(frame.size()), 0.0f);
  frameShading(header, frame.data(), background.data(), static_cast<int>(channels),
               out.mutable_data(), keepNegative);
  return out;
}

}  // namespace acpca::python
