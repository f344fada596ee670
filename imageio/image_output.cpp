#include "imageio/image_output.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/half.h"
#include "imageio/image_file.h"
#include "imageio/npy_file.h"

namespace acpca {

namespace {
/// A writing thread's scratch for one frame's values, kept from frame to
/// frame: a fresh 1024x1024 frame's worth is megabytes of pages the kernel
/// zeroes first, as long as encoding it.
template <typename T>
std::vector<T>& frameScratch(size_t values) {
  thread_local std::vector<T> scratch;
  scratch.resize(values);
  return scratch;
}

/// The image's values times `scale` but alpha (coverage): the pixels
/// themselves when the scale is 1.
const float* scaledPixels(const Image& image, float scale) {
  if (scale == 1) return image.pixels.data();
  std::vector<float>& scaled = frameScratch<float>(image.pixels.size());
  for (size_t i = 0; i < scaled.size(); ++i)
    scaled[i] = (image.channels == 4 && i % 4 == 3) ? image.pixels[i] : image.pixels[i] * scale;
  return scaled.data();
}
}  // namespace

void encodePng8(int width, int height, int channels, const unsigned char* values,
                const std::string& file, const std::string& path, int level,
                const FrameMetadata* metadata) {
  ImageWriteSpec spec{width, height, channels, PixelType::UInt8};
  spec.integerAttributes = {{"png:compressionLevel", std::clamp(level, 0, 9)}};
  spec.metadata = metadata;
  writeImageFile(file, spec, values, path);
}

void encodePng(const Image& image, const std::string& file, const std::string& path,
               double exposureEv, const ImageEncoding& encoding) {
  std::vector<unsigned char>& bytes = frameScratch<unsigned char>(0);
  SrgbEncoder(exposureEv, encoding.tone).encodeInto(image, bytes);
  encodePng8(image.width, image.height, image.channels, bytes.data(), file, path, encoding.pngLevel,
             encoding.metadata);
}

/// 16-bit sRGB (Srgb16Encoder), alpha as coverage.
void encodePng16(const Image& image, const std::string& file, const std::string& path,
                 double exposureEv, const ImageEncoding& encoding) {
  std::vector<std::uint16_t>& values = frameScratch<std::uint16_t>(0);
  Srgb16Encoder(exposureEv, encoding.tone).encodeInto(image, values);
  ImageWriteSpec spec{image.width, image.height, image.channels, PixelType::UInt16};
  spec.integerAttributes = {{"png:compressionLevel", std::clamp(encoding.pngLevel, 0, 9)}};
  spec.metadata = encoding.metadata;
  writeImageFile(file, spec, values.data(), path);
}

/// float32 H x W x C, linear, times 2^exposure (alpha as coverage).
void encodeNpy(const Image& image, const std::string& file, const std::string& path,
               double exposureEv, const ImageEncoding&) {
  writeNpy(file, path,
           {static_cast<size_t>(image.height), static_cast<size_t>(image.width),
            static_cast<size_t>(image.channels)},
           scaledPixels(image, static_cast<float>(std::exp2(exposureEv))));
}

void encodeExr(const Image& image, const std::string& file, const std::string& path,
               double exposureEv, const ImageEncoding& encoding) {
  const size_t values = image.pixels.size();
  ImageWriteSpec spec{image.width, image.height, image.channels,
                      encoding.exrFloat ? PixelType::Float : PixelType::Half};
  // OpenImageIO stamps EXRs with the time of writing unless told otherwise:
  // the same inputs must give the same bytes (datasets are compared by hash).
  spec.textAttributes = {{"compression", kExrCompressionNames.name(encoding.exrCompression)},
                         {"DateTime", ""}};
  spec.metadata = encoding.metadata;
  const float* pixels = scaledPixels(image, static_cast<float>(std::exp2(exposureEv)));
  if (encoding.exrFloat) return writeImageFile(file, spec, pixels, path);
  // Halves made by the CPU's instruction, the same IEEE rounding as
  // OpenEXR's, so the same file.
  std::vector<std::uint16_t>& halves = frameScratch<std::uint16_t>(values);
  floatToHalfIeee(pixels, halves.data(), values);
  writeImageFile(file, spec, halves.data(), path);
}

void encodeImage(const Image& image, const std::string& file, const std::string& path,
                 ImageFormat format, double exposureEv, const ImageEncoding& encoding) {
  const ImageFormatRow& row = imageFormatRow(format);
  ACPCA_CHECK(image.channels >= 1 && image.channels <= row.maxChannels, "an image of ",
              image.channels, " channels cannot be written as ", row.name);
  row.encode(image, file, path, exposureEv, encoding);
}

void writeImage(const Image& image, const std::string& path, ImageFormat format, double exposureEv,
                bool exrFloat) {
  AtomicOutput output(path);  // the temporary name keeps the extension that picks the codec
  ImageEncoding encoding;
  encoding.exrFloat = exrFloat;
  encodeImage(image, output.tempPath(), path, format, exposureEv, encoding);
  output.commit();
}

void writePng8(int width, int height, int channels, const unsigned char* values,
               const std::string& path) {
  AtomicOutput output(path);
  encodePng8(width, height, channels, values, output.tempPath(), path, ImageEncoding{}.pngLevel);
  output.commit();
}

}  // namespace acpca
