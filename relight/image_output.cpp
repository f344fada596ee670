#include "relight/image_output.h"

#include <OpenImageIO/imageio.h>

#include <cmath>

#include "precompute/transport/atomic_file.h"
#include "precompute/transport/error.h"

namespace acpca {

Background parseBackground(const std::string& text) {
  if (text == "env") return Background::Env;
  if (text == "black") return Background::Black;
  if (text == "alpha") return Background::Alpha;
  throw UserError(concat("--background '", text, "' is not one of env, black, alpha"));
}

double linearToSrgb(double v) {
  v = std::clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

Image composeImage(const TransportHeader& header, const std::vector<float>& rowRgb,
                   Background background, const Environment& env, const Eigen::Matrix3d& rotation) {
  const Camera& camera = header.camera;
  Image image;
  image.width = camera.size.width;
  image.height = camera.size.height;
  image.channels = background == Background::Alpha ? 4 : 3;
  image.pixels.assign(static_cast<size_t>(image.width) * image.height * image.channels, 0.0f);
  std::vector<float> coverage(static_cast<size_t>(camera.size.pixels()), 0.0f);
  for (long long r = 0; r < header.rows(); ++r) coverage[header.pixels[r]] = header.coverage[r];
  const Eigen::Matrix3d inverse = rotation.transpose();
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      float* out = image.at(x, y);
      const float cov = coverage[static_cast<size_t>(y) * image.width + x];
      if (background == Background::Env && cov < 1) {
        const Rgb bg = env.radiance(inverse * camera.rayDirection(x + 0.5, y + 0.5));
        for (int c = 0; c < 3; ++c) out[c] = float((1 - cov) * bg[c]);
      }
      if (background == Background::Alpha) out[3] = cov;
    }
  for (long long r = 0; r < header.rows(); ++r) {
    const int p = header.pixels[r];
    float* out = image.at(p % image.width, p / image.width);
    for (int c = 0; c < 3; ++c) out[c] += header.coverage[r] * rowRgb[3 * r + c];
  }
  return image;
}

void writeImage(const Image& image, const std::string& path, ImageFormat format, double exposureEv,
                bool exrFloat) {
  AtomicOutput output(path);
  auto out = OIIO::ImageOutput::create(output.tempPath());
  if (!out) throw UserError(concat(path, ": cannot create an image writer: ", OIIO::geterror()));
  const float scale = static_cast<float>(std::exp2(exposureEv));
  const size_t values = image.pixels.size();
  bool ok;
  if (format == ImageFormat::Exr) {
    OIIO::ImageSpec spec(image.width, image.height, image.channels,
                         exrFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF);
    spec.attribute("compression", "zips");
    std::vector<float> scaled(values);
    for (size_t i = 0; i < values; ++i)
      scaled[i] = (image.channels == 4 && i % 4 == 3) ? image.pixels[i] : image.pixels[i] * scale;
    ok = out->open(output.tempPath(), spec) &&
         out->write_image(OIIO::TypeDesc::FLOAT, scaled.data()) && out->close();
  } else {
    OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
    std::vector<unsigned char> bytes(values);
    for (size_t i = 0; i < values; ++i) {
      const bool alpha = image.channels == 4 && i % 4 == 3;
      const double v = alpha ? std::clamp(double(image.pixels[i]), 0.0, 1.0)
                             : linearToSrgb(image.pixels[i] * scale);
      bytes[i] = static_cast<unsigned char>(std::lround(v * 255));
    }
    ok = out->open(output.tempPath(), spec) &&
         out->write_image(OIIO::TypeDesc::UINT8, bytes.data()) && out->close();
  }
  if (!ok) throw UserError(concat(path, ": cannot write the image: ", out->geterror()));
  output.commit();
}

}  // namespace acpca
