#pragma once
// What the end-to-end suites read back of the images the CLI wrote.
#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

namespace acpca::test {

/// Every channel of an image file's pixels as float, row by row; empty when
/// it cannot be read.
inline std::vector<float> readPixels(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> pixels(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, -1, OIIO::TypeDesc::FLOAT, pixels.data())) return {};
  return pixels;
}

}  // namespace acpca::test
