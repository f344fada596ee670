#pragma once
// Linear values to the 8- and 16-bit sRGB codes PNG output writes, exactly and
// fast, after an exposure and a tone curve.
#include <array>
#include <cstdint>
#include <vector>

#include "core/enum_names.h"
#include "imageio/image.h"

namespace acpca {

/// How PNG output maps linear values (after exposure) into [0, 1] before the
/// sRGB transfer function: clamp, or the ACES filmic curve as fitted by
/// Narkowicz (2015, "ACES Filmic Tone Mapping Curve"):
/// x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1].
enum class ToneCurve { Clamp, Aces };
inline constexpr EnumNames<ToneCurve, 2> kToneCurveNames{
    "tone curve", {{{ToneCurve::Clamp, "clamp"}, {ToneCurve::Aces, "aces"}}}};
/// The curve's value of a linear value, in [0, 1].
double toneMapped(double linear, ToneCurve tone);

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
