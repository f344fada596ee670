#pragma once
// Relit images: composing per-pixel results with the background, and writing
// linear EXR or tone-mapped sRGB PNG (always to a temporary name, then renamed).
#include <string>
#include <vector>

#include "precompute/transport/transport_file.h"
#include "relight/environment.h"

namespace acpca {

struct Image {
  int width = 0, height = 0, channels = 3;
  std::vector<float> pixels;  ///< row-major, row 0 at the top
  float* at(int x, int y) { return &pixels[(static_cast<size_t>(y) * width + x) * channels]; }
  const float* at(int x, int y) const {
    return &pixels[(static_cast<size_t>(y) * width + x) * channels];
  }
};

enum class Background { Env, Black, Alpha };
Background parseBackground(const std::string& text);  // env | black | alpha

enum class ImageFormat { Exr, Png };

/// Places per-row RGB (albedo applied) into the image. Background pixels (and
/// the uncovered part of silhouette pixels) show the rotated environment, black,
/// or transparency (RGBA, alpha = coverage).
Image composeImage(const TransportHeader& header, const std::vector<float>& rowRgb,
                   Background background, const Environment& env, const Eigen::Matrix3d& rotation);

/// Writes EXR (linear, half by default) or PNG (x 2^exposure, sRGB, 8-bit).
/// EXR output is also scaled by 2^exposure. Throws UserError naming the path.
void writeImage(const Image& image, const std::string& path, ImageFormat format, double exposureEv,
                bool exrFloat = false);

/// sRGB transfer function of a linear value in [0, 1].
double linearToSrgb(double v);

}  // namespace acpca
