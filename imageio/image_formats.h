#pragma once
// The image formats frames are written in, one row each: its name, extension,
// the bytes a value takes and its encoder. A new format is an enum value, a
// row and its encoder (docs/architecture.md, "Where new things go").
#include <array>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "imageio/image.h"
#include "imageio/srgb_encoders.h"

namespace acpca {

struct FrameMetadata;  // imageio/frame_metadata.h

/// EXR (linear, half or float), PNG (sRGB, 8 or 16 bits, tone mapped) or
/// NumPy .npy (linear float32, H x W x C).
enum class ImageFormat { Exr, Png, Png16, Npy };

/// EXR codecs (all lossless), by OpenEXR's names.
enum class ExrCompression { None, Rle, Zips, Zip, Piz };
inline constexpr EnumNames<ExrCompression, 5> kExrCompressionNames{
    "EXR compression",
    {{{ExrCompression::None, "none"},
      {ExrCompression::Rle, "rle"},
      {ExrCompression::Zips, "zips"},
      {ExrCompression::Zip, "zip"},
      {ExrCompression::Piz, "piz"}}}};

/// How an image file is encoded: EXR values in half or float and their codec,
/// PNG's deflate level (0-9; zlib's 6 unless told) and tone curve.
struct ImageEncoding {
  bool exrFloat = false;
  ExrCompression exrCompression = ExrCompression::Zips;
  int pngLevel = 6;
  ToneCurve tone = ToneCurve::Clamp;
  /// What the file says of the frame (PNG and EXR; imageio/frame_metadata.h):
  /// null, nothing.
  const FrameMetadata* metadata = nullptr;
};

/// Writes `image` times 2^exposure (alpha, coverage, unscaled) into `file`, a
/// temporary name the caller renames; errors name `path`.
using ImageEncoder = void (*)(const Image& image, const std::string& file, const std::string& path,
                              double exposureEv, const ImageEncoding& encoding);
void encodeExr(const Image&, const std::string&, const std::string&, double, const ImageEncoding&);
void encodePng(const Image&, const std::string&, const std::string&, double, const ImageEncoding&);
void encodePng16(const Image&, const std::string&, const std::string&, double,
                 const ImageEncoding&);
void encodeNpy(const Image&, const std::string&, const std::string&, double, const ImageEncoding&);

struct ImageFormatRow {
  ImageFormat format;
  const char* name;       ///< as --format names it
  const char* extension;  ///< dot included; formats may share one (png, png16)
  int bytesPerValue;      ///< stored, before compression (EXR: half)
  int bytesPerFloat;      ///< the same with ImageEncoding::exrFloat
  int maxChannels;        ///< 1 to this many channels a pixel
  ImageEncoder encode;
};
inline constexpr std::array<ImageFormatRow, 4> kImageFormats{{
    {ImageFormat::Exr, "exr", ".exr", 2, 4, 4, &encodeExr},
    {ImageFormat::Png, "png", ".png", 1, 1, 4, &encodePng},
    {ImageFormat::Png16, "png16", ".png", 2, 2, 4, &encodePng16},
    {ImageFormat::Npy, "npy", ".npy", 4, 4, 4, &encodeNpy},
}};

/// The formats' names from their rows, so parsing and listing cannot drift.
inline constexpr EnumNames<ImageFormat, kImageFormats.size()> kImageFormatNames{
    "image format", [] {
      std::array<std::pair<ImageFormat, const char*>, kImageFormats.size()> names{};
      for (size_t i = 0; i < kImageFormats.size(); ++i)
        names[i] = {kImageFormats[i].format, kImageFormats[i].name};
      return names;
    }()};

/// The row of a format.
const ImageFormatRow& imageFormatRow(ImageFormat format);
/// A format's file extension, dot included (png16 writes .png).
inline const char* imageExtension(ImageFormat format) {
  return imageFormatRow(format).extension;
}
/// The bytes one value of a frame takes in `format`, before compression.
int storedBytesPerValue(ImageFormat format, const ImageEncoding& encoding);
/// The first format written with `extension` (dot included): ".png" is 8-bit
/// PNG. Nullptr when none is.
const ImageFormatRow* imageFormatOfExtension(const std::string& extension);
/// A comma-separated list of format names, each format once and no two of one
/// extension (png and png16 would write the same file): a ParameterError
/// naming "image format" otherwise.
std::vector<ImageFormat> parseImageFormatList(const std::string& list);

}  // namespace acpca
