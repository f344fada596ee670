#pragma once
// Relit images written: linear EXR, tone-mapped sRGB PNG, 16-bit PNG or NumPy
// (always to a temporary name, then renamed).
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "core/srgb.h"
#include "relight/image_composer.h"

namespace acpca {

/// EXR (linear, half or float), PNG (sRGB, 8 or 16 bits, tone mapped) or
/// NumPy .npy (linear float32, H x W x C).
enum class ImageFormat { Exr, Png, Png16, Npy };
inline constexpr EnumNames<ImageFormat, 4> kImageFormatNames{"image format",
                                                             {{{ImageFormat::Exr, "exr"},
                                                               {ImageFormat::Png, "png"},
                                                               {ImageFormat::Png16, "png16"},
                                                               {ImageFormat::Npy, "npy"}}}};
/// A format's file extension, dot included (png16 writes .png).
const char* imageExtension(ImageFormat format);

/// How PNG output maps linear values (after exposure) into [0, 1] before the
/// sRGB transfer function: clamp, or the ACES filmic curve as fitted by
/// Narkowicz (2015, "ACES Filmic Tone Mapping Curve"):
/// x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1].
enum class ToneCurve { Clamp, Aces };
inline constexpr EnumNames<ToneCurve, 2> kToneCurveNames{
    "tone curve", {{{ToneCurve::Clamp, "clamp"}, {ToneCurve::Aces, "aces"}}}};
/// The curve's value of a linear value, in [0, 1].
double toneMapped(double linear, ToneCurve tone);

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
};

/// Writes EXR (linear, half by default) or PNG (x 2^exposure, sRGB, 8-bit).
/// EXR output is also scaled by 2^exposure. Throws UserError naming the path.
void writeImage(const Image& image, const std::string& path, ImageFormat format, double exposureEv,
                bool exrFloat = false);
/// The same into `file` (a temporary name the caller renames; errors name
/// `path`), encoded as told.
void encodeImage(const Image& image, const std::string& file, const std::string& path,
                 ImageFormat format, double exposureEv, const ImageEncoding& encoding);

/// 8-bit values (rows top to bottom, channels interleaved) as PNG into
/// `file` (a temporary name the caller renames; errors name `path`).
void encodePng8(int width, int height, int channels, const unsigned char* values,
                const std::string& file, const std::string& path, int level);
/// Writes 8-bit values as PNG, atomically; throws UserError naming the path.
void writePng8(int width, int height, int channels, const unsigned char* values,
               const std::string& path);

/// 8-bit sRGB of linear values times 2^exposure, as PNG output writes them:
/// round(255 * linearToSrgb(tone(v * scale))). Exact and fast: the code is found
/// among the 255 float thresholds where it steps up (the map is monotone), so
/// a viewer shows the very bytes a batch PNG holds.
class SrgbEncoder {
 public:
  explicit SrgbEncoder(double exposureEv, ToneCurve tone = ToneCurve::Clamp);
  unsigned char operator()(float linear) const;
  /// Every channel of the image (alpha, if any, is coverage in [0, 1], not tone mapped).
  std::vector<unsigned char> encode(const Image& image) const;
  /// The same into `bytes` (resized), whose storage a caller may keep.
  void encodeInto(const Image& image, std::vector<unsigned char>& bytes) const;

 private:
  static constexpr int kBucketExponents = 16, kBucketBits = 7;
  static constexpr std::uint32_t kFirstBucket = std::uint32_t(127 - kBucketExponents) << 23;
  struct Tables {
    Tables();
    std::array<float, 256> thresholds;  ///< [b]: smallest scaled value whose code is b + 1
    /// Code at the start of each bucket of scaled values in [2^-kBucketExponents, 1),
    /// a bucket per exponent and top kBucketBits mantissa bits; the exact code is
    /// at most a step or two above it.
    std::array<unsigned char, (kBucketExponents << kBucketBits)> bucketCode;
  };
  static const Tables& tables();
  /// The code of an exposed (and tone-mapped) value.
  unsigned char codeOfScaled(float scaled) const;

  float scale_;
  ToneCurve tone_;
  const Tables& tables_;
};

/// 16-bit sRGB as png16 output writes it: round(65535 * linearToSrgb(tone(v
/// 2^exposure))) in double. Exact by the same construction as SrgbEncoder:
/// the 65,535 double thresholds where the code steps up, found by bisection
/// over the formula itself, and a table of buckets of the curve's value that
/// leaves a step or two to walk. Built once, on first use (about 20 ms).
class Srgb16Encoder {
 public:
  explicit Srgb16Encoder(double exposureEv = 0, ToneCurve tone = ToneCurve::Clamp);
  std::uint16_t operator()(float linear) const;
  /// Every channel of the image into `values` (resized); alpha, if any, is
  /// coverage: round(65535 clamp(a, 0, 1)).
  void encodeInto(const Image& image, std::vector<std::uint16_t>& values) const;

 private:
  static constexpr int kBucketExponents = 24, kBucketBits = 12;
  static constexpr std::uint64_t kFirstBucket = std::uint64_t(1023 - kBucketExponents) << 52;
  struct Tables {
    Tables();
    std::vector<double> thresholds;         ///< [c]: smallest curve value whose code is c + 1
    std::vector<std::uint16_t> bucketCode;  ///< code at the start of each bucket
  };
  static const Tables& tables();

  double scale_;
  ToneCurve tone_;
  const Tables& tables_;
};

}  // namespace acpca
