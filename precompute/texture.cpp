#include "precompute/texture.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/warning.h"
#include "imageio/image_file.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// Larger textures than this (in texels) are refused as corrupt headers.
constexpr long long kMaxTexels = 1LL << 28;

std::shared_ptr<const Texture> readOpened(ImageReader& in, const std::string& name) {
  const ImageHeader& header = in.header();
  if (header.width < 1 || header.height < 1 || header.depth != 1 ||
      static_cast<long long>(header.width) * header.height > kMaxTexels)
    throw UserError(
        concat(name, ": texture size ", header.width, "x", header.height, " is out of range"));
  if (header.channels < 1) throw UserError(concat(name, ": the texture has no channels"));
  // Grey (with or without alpha) or the first three channels; alpha is not used.
  const int channels = header.channels >= 3 ? 3 : 1;
  const size_t texels = static_cast<size_t>(header.width) * header.height;
  std::vector<float> values(texels * channels);
  if (!in.readImage(0, channels, PixelType::Float, values.data()))
    throw UserError(concat(name, ": cannot read the texture pixels: ", in.error()));
  const std::string& colorSpace = header.colorSpace;
  const bool integer = header.stored != StoredValues::FloatingPoint;
  const bool encoded = integer && colorSpace != "Linear" && colorSpace != "linear";
  std::vector<float> rgb(texels * 3);
  long long negatives = 0;
  for (size_t t = 0; t < texels; ++t)
    for (int c = 0; c < 3; ++c) {
      float v = values[t * channels + (channels == 3 ? c : 0)];
      if (!std::isfinite(v))
        throw UserError(
            concat(name, ": texel (", t % header.width, ", ", t / header.width, ") is not finite"));
      if (v < 0) ++negatives, v = 0;
      rgb[3 * t + c] = encoded ? static_cast<float>(srgbToLinear(v)) : v;
    }
  if (negatives > 0) warn(concat(name, ": ", negatives, " negative texel values clamped to 0"));
  return std::make_shared<const Texture>(name, header.width, header.height, std::move(rgb));
}

/// Colour as stored: OpenImageIO would otherwise multiply PNG colours by alpha.
constexpr ImageReadOptions kAsStored{true};

}  // namespace

Texture::Texture(std::string name, int width, int height, std::vector<float> rgb)
    : name_(std::move(name)), width_(width), height_(height), rgb_(std::move(rgb)) {
  ACPCA_CHECK(width_ > 0 && height_ > 0 && rgb_.size() == 3 * size_t(width_) * height_, "texture '",
              name_, "' of ", width_, "x", height_, " with ", rgb_.size(), " values");
}

Eigen::Vector3f Texture::texel(int x, int y) const {
  const float* p = &rgb_[3 * (static_cast<size_t>(y) * width_ + x)];
  return {p[0], p[1], p[2]};
}

Eigen::Vector3f Texture::sample(const Eigen::Vector2f& uv) const {
  // Continuous texel coordinates with texel centres at integers + 0.5; v runs
  // up while image rows run down.
  const double fx = double(uv.x()) * width_ - 0.5;
  const double fy = (1 - double(uv.y())) * height_ - 0.5;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  const float tx = float(fx - x0), ty = float(fy - y0);
  const auto wrap = [](double i, int n) {
    const long long m = static_cast<long long>(std::fmod(i, double(n)));
    return static_cast<int>(m < 0 ? m + n : m);
  };
  const int xa = wrap(x0, width_), xb = wrap(x0 + 1, width_);
  const int ya = wrap(y0, height_), yb = wrap(y0 + 1, height_);
  return (1 - ty) * ((1 - tx) * texel(xa, ya) + tx * texel(xb, ya)) +
         ty * ((1 - tx) * texel(xa, yb) + tx * texel(xb, yb));
}

std::shared_ptr<const Texture> loadTexture(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw UserError(concat(path, ": texture file not found"));
  std::string error;
  auto in = openImage(path, error, kAsStored);
  if (!in) throw UserError(concat(path, ": cannot read the texture: ", error));
  return readOpened(*in, path);
}

std::shared_ptr<const Texture> loadTextureFromMemory(const std::string& name,
                                                     const std::string& formatHint,
                                                     const void* bytes, size_t size) {
  // Not every OpenImageIO reader takes its bytes from memory (PNG does not in
  // 2.4): the image goes through a private temporary file named for its format.
  static std::atomic<int> counter{0};
  const fs::path file =
      fs::temp_directory_path() / concat("acpca-texture-", ::getpid(), "-", counter++, ".",
                                         formatHint.empty() ? "png" : formatHint);
  struct Removed {
    fs::path path;
    ~Removed() {
      std::error_code ignored;
      fs::remove(path, ignored);
    }
  } removed{file};
  {
    std::ofstream out(file, std::ios::binary);
    out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
    if (!out) throw UserError(concat(name, ": cannot write it to ", file.string()));
  }
  std::string error;
  auto in = openImage(file.string(), error, kAsStored);
  if (!in)
    throw UserError(concat(name, ": cannot read the embedded '", formatHint, "' texture: ", error));
  return readOpened(*in, name);
}

}  // namespace acpca
