#pragma once
// Textures for the suites that load them: 8-bit images written with
// OpenImageIO, and the sRGB decoding written out from its definition (IEC
// 61966-2-1) so that the renderer's own decoder is checked against it.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace acpca::test {

/// Writes width x height 8-bit texels (channels per texel, top row first).
inline void writeImage8(const std::string& path, int width, int height, int channels,
                        const std::vector<unsigned char>& texels) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << path;
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // the texels as given, not divided by alpha
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, texels.data()));
  out->close();
}

/// Linear value of an 8-bit sRGB code.
inline double srgbCodeToLinear(int code) {
  const double c = code / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

}  // namespace acpca::test
