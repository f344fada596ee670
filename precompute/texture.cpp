#include "precompute/texture.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/warning.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// Larger textures than this (in texels) are refused as corrupt headers.
constexpr long long kMaxTexels = 1LL << 28;

std::shared_ptr<const Texture> readOpened(OIIO::ImageInput& in, const std::string& name) {
  const OIIO::ImageSpec& spec = in.spec();
  if (spec.width < 1 || spec.height < 1 || spec.depth != 1 ||
      static_cast<long long>(spec.width) * spec.height > kMaxTexels)
    throw UserError(
        concat(name, ": texture size ", spec.width, "x", spec.height, " is out of range"));
  if (spec.nchannels < 1) throw UserError(concat(name, ": the texture has no channels"));
  // Grey (with or without alpha) or the first three channels; alpha is not used.
  const int channels = spec.nchannels >= 3 ? 3 : 1;
  const size_t texels = static_cast<size_t>(spec.width) * spec.height;
  std::vector<float> values(texels * channels);
  if (!in.read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, values.data()))
    throw UserError(concat(name, ": cannot read the texture pixels: ", in.geterror()));
  const std::string colorSpace = spec.get_string_attribute("oiio:ColorSpace");
  const bool integer = !spec.format.is_floating_point();
  const bool encoded = integer && colorSpace != "Linear" && colorSpace != "linear";
  std::vector<float> rgb(texels * 3);
  long long negatives = 0;
  for (size_t t = 0; t < texels; ++t)
    for (int c = 0; c < 3; ++c) {
      float v = values[t * channels + (channels == 3 ? c : 0)];
      if (!std::isfinite(v))
        throw UserError(
            concat(name, ": texel (", t % spec.width, ", ", t / spec.width, ") is not finite"));
      if (v < 0) ++negatives, v = 0;
      rgb[3 * t + c] = encoded ? static_cast<float>(srgbToLinear(v)) : v;
    }
  if (negatives > 0) warn(concat(name, ": ", negatives, " negative texel values clamped to 0"));
  return std::make_shared<const Texture>(name, spec.width, spec.height, std::move(rgb));
}

/// Colour as stored: OpenImageIO would otherwise multiply PNG colours by alpha.
OIIO::ImageSpec readConfig() {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  return config;
}

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
  if (!OIIO::Filesystem::is_regular(path))
    throw UserError(concat(path, ": texture file not found"));
  const OIIO::ImageSpec config = readConfig();
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw UserError(concat(path, ": cannot read the texture: ", OIIO::geterror()));
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
  const OIIO::ImageSpec config = readConfig();
  auto in = OIIO::ImageInput::open(file.string(), &config);
  if (!in)
    throw UserError(
        concat(name, ": cannot read the embedded '", formatHint, "' texture: ", OIIO::geterror()));
  return readOpened(*in, name);
}

}  // namespace acpca
