#pragma once
// Relit images: composing per-pixel results with the background, and writing
// linear EXR or tone-mapped sRGB PNG (always to a temporary name, then renamed).
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "core/srgb.h"
#include "relight/environment.h"
#include "transport/transport_file.h"

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
inline constexpr EnumNames<Background, 3> kBackgroundNames{
    "background",
    {{{Background::Env, "env"}, {Background::Black, "black"}, {Background::Alpha, "alpha"}}}};
Background parseBackground(const std::string& text);  // env | black | alpha
/// Refuses Background::Env for a captured light set, which has no camera to
/// see the environment through: a ParameterError naming "background" and `path`.
void requireBackgroundShown(const TransportHeader& header, Background background,
                            const std::string& path);

/// What clamping a frame at zero changed (docs/design.md, section 6): a
/// model's reconstruction undershoots where the transport is zero or small,
/// and no surface emits negative light.
struct NegativeClamp {
  long long values = 0;    ///< colour values that were below zero
  float mostNegative = 0;  ///< the lowest of them (0 when none)
  void add(const NegativeClamp& other) {
    values += other.values;
    mostNegative = std::min(mostNegative, other.mostNegative);
  }
};
/// Raises every negative colour value of an image of `channels` floats per
/// pixel to 0 (the alpha of 4 channels is coverage, never negative) and says
/// what changed; `keep` counts them and changes nothing.
NegativeClamp clampNegative(float* pixels, size_t values, int channels, bool keep = false);

/// EXR (linear, half or float), PNG (sRGB, 8 or 16 bits, tone mapped) or
/// NumPy .npy (linear float32, H x W x C).
enum class ImageFormat { Exr, Png, Png16, Npy };

/// How PNG output maps linear values (after exposure) into [0, 1] before the
/// sRGB transfer function: clamp, or the ACES filmic curve as fitted by
/// Narkowicz (2015, "ACES Filmic Tone Mapping Curve"):
/// x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1].
enum class ToneCurve { Clamp, Aces };
inline constexpr EnumNames<ToneCurve, 2> kToneCurveNames{
    "tone curve", {{{ToneCurve::Clamp, "clamp"}, {ToneCurve::Aces, "aces"}}}};
/// The curve's value of a linear value, in [0, 1].
double toneMapped(double linear, ToneCurve tone);

/// Places per-row RGB (albedo applied) into the image. Background pixels (and
/// the uncovered part of silhouette pixels) show the rotated environment, black,
/// or transparency (RGBA, alpha = coverage).
Image composeImage(const TransportHeader& header, const std::vector<float>& rowRgb,
                   Background background, const Environment& env, const Eigen::Matrix3d& rotation);
/// The same into `pixels`: width x height x channels floats (4 with Alpha,
/// else 3), every value written.
void composeInto(const TransportHeader& header, const float* rowRgb, Background background,
                 const Environment& env, const Eigen::Matrix3d& rotation, float* pixels);

/// Composes the frames of one camera (the coverage image is built once): the
/// background first, then each occupied pixel's relit value added, from rows
/// (addRows) or straight from the relighter (ModelRelighter::relightInto).
/// Keeps its own copy of what it needs from the header.
class ImageComposer {
 public:
  explicit ImageComposer(const TransportHeader& header);
  static int channels(Background background) { return background == Background::Alpha ? 4 : 3; }
  /// Every pixel's background part: (1 - coverage) x the environment seen
  /// through it (Env) or 0, and alpha = coverage (Alpha). `silhouettesOnly`:
  /// the environment only where an object covers part of the pixel (what a
  /// frame's shading takes away), 0 at pure background.
  void background(Background background, const Environment& env, const Eigen::Matrix3d& rotation,
                  float* pixels, bool silhouettesOnly = false) const;
  /// Adds coverage x rowRgb (3 floats per row) at each row's pixel.
  void addRows(const float* rowRgb, float* pixels, int channels) const;

 private:
  Camera camera_;
  std::vector<std::int32_t> rowPixels_;  ///< pixel of each row
  std::vector<float> rowCoverage_;       ///< coverage of each row
  std::vector<float> coverage_;          ///< per pixel, 0 for background
  /// Pixels with coverage below 1 (row by row), and the camera ray through each.
  std::vector<size_t> backgroundPixel_, backgroundRowStart_;
  std::vector<Vec3> backgroundRay_;
};

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

/// Writes 8-bit values (rows top to bottom, channels interleaved) as PNG,
/// atomically; throws UserError naming the path.
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

  float scale_;
  ToneCurve tone_;
  const Tables& tables_;
};

}  // namespace acpca
