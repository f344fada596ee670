#include "imageio/srgb_encoders.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/error.h"
#include "core/srgb.h"

namespace acpca {

double toneMapped(double v, ToneCurve tone) {
  if (tone == ToneCurve::Aces && v > 0) v = v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14);
  return std::clamp(v, 0.0, 1.0);
}

namespace {
/// The 8-bit code of a scaled linear value, by the formula itself.
unsigned char srgbCode(float scaled) {
  return static_cast<unsigned char>(std::lround(linearToSrgb(scaled) * 255));
}

/// The 16-bit code of a curve value in [0, 1], by the formula itself.
std::uint16_t srgb16Code(double curve) {
  return static_cast<std::uint16_t>(std::lround(linearToSrgb(curve) * 65535));
}
}  // namespace

Srgb16Encoder::Tables::Tables() : thresholds(65536), bucketCode(kBucketExponents << kBucketBits) {
  // Non-negative doubles order like their bit patterns: each threshold is the
  // smallest x with srgb16Code(x) > c, by bisection over the bits, started
  // around the exact inverse and widened until it brackets the step.
  const std::uint64_t one = std::bit_cast<std::uint64_t>(1.0);  // srgb16Code(1) = 65535
  for (int c = 0; c < 65535; ++c) {
    const std::uint64_t guess = std::bit_cast<std::uint64_t>(srgbToLinear((c + 0.5) / 65535));
    std::uint64_t span = std::uint64_t(1) << 20;
    std::uint64_t lo = guess > span ? guess - span : 0, hi = std::min(guess + span, one);
    while (srgb16Code(std::bit_cast<double>(lo)) > c) lo = lo > span ? lo - (span <<= 1) : 0;
    while (hi < one && srgb16Code(std::bit_cast<double>(hi)) <= c)
      hi = std::min(hi + (span <<= 1), one);
    while (lo < hi) {
      const std::uint64_t mid = lo + (hi - lo) / 2;
      if (srgb16Code(std::bit_cast<double>(mid)) > c)
        hi = mid;
      else
        lo = mid + 1;
    }
    thresholds[c] = std::bit_cast<double>(lo);
  }
  thresholds[65535] = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < bucketCode.size(); ++k)
    bucketCode[k] =
        srgb16Code(std::bit_cast<double>(kFirstBucket + (std::uint64_t(k) << (52 - kBucketBits))));
}

Srgb16Encoder::Srgb16Encoder(double exposureEv, ToneCurve tone)
    : scale_(std::exp2(exposureEv)), tone_(tone), tables_(tables()) {}

const Srgb16Encoder::Tables& Srgb16Encoder::tables() {
  static const Tables shared;
  return shared;
}

std::uint16_t Srgb16Encoder::operator()(float linear) const {
  const double curve = toneMapped(double(linear) * scale_, tone_);
  if (!(curve > 0)) return 0;  // zero or NaN
  if (curve >= 1) return 65535;
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(curve);
  int code =
      bits < kFirstBucket ? 0 : tables_.bucketCode[(bits - kFirstBucket) >> (52 - kBucketBits)];
  while (curve >= tables_.thresholds[code]) ++code;  // thresholds[65535] is infinite
  return static_cast<std::uint16_t>(code);
}

void Srgb16Encoder::encodeInto(const Image& image, std::vector<std::uint16_t>& values) const {
  values.resize(image.pixels.size());
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, values.size(), 1 << 14),
      [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i)
          values[i] = image.channels == 4 && i % 4 == 3
                          ? static_cast<std::uint16_t>(
                                std::lround(std::clamp(double(image.pixels[i]), 0.0, 1.0) * 65535))
                          : (*this)(image.pixels[i]);
      });
}

SrgbEncoder::Tables::Tables() {
  // Non-negative floats order like their bit patterns, so each threshold is
  // found by bisection over the bits: the smallest x with srgbCode(x) > b.
  for (int b = 0; b < 255; ++b) {
    std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1.0f);  // srgbCode(1) = 255
    while (lo < hi) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      if (srgbCode(std::bit_cast<float>(mid)) > b)
        hi = mid;
      else
        lo = mid + 1;
    }
    thresholds[b] = std::bit_cast<float>(lo);
  }
  thresholds[255] = std::numeric_limits<float>::infinity();
  for (size_t k = 0; k < bucketCode.size(); ++k)
    bucketCode[k] =
        srgbCode(std::bit_cast<float>(kFirstBucket + (std::uint32_t(k) << (23 - kBucketBits))));
  // The two steps codeOfScaled takes reach any code inside a bucket.
  for (size_t k = 0; k < bucketCode.size(); ++k)
    ACPCA_CHECK((k + 1 < bucketCode.size() ? bucketCode[k + 1] : 255) - bucketCode[k] <= 2,
                "sRGB bucket ", k, " spans more than two codes");
}

// The tables hold scaled values, so one set serves every exposure; built once
// (7,650 pow calls), not once a frame.
SrgbEncoder::SrgbEncoder(double exposureEv, ToneCurve tone)
    : scale_(static_cast<float>(std::exp2(exposureEv))), tone_(tone), tables_(tables()) {}

const SrgbEncoder::Tables& SrgbEncoder::tables() {
  static const Tables shared;
  return shared;
}

unsigned char SrgbEncoder::codeOfScaled(float scaled) const {
  // Without branches: negatives and NaN become 0, 1 and above the float just
  // below 1 (code 255 either way), values below the first bucket its start
  // (code 0 either way); the bucket's code is then at most two steps short.
  constexpr float kBelowOne = 0x1.fffffep-1f;
  const float s = scaled > 0 ? std::min(scaled, kBelowOne) : 0.0f;
  const std::uint32_t bits = std::max(std::bit_cast<std::uint32_t>(s), kFirstBucket);
  int code = tables_.bucketCode[(bits - kFirstBucket) >> (23 - kBucketBits)];
  code += s >= tables_.thresholds[code];  // thresholds[255] is infinite
  code += s >= tables_.thresholds[code];
  return static_cast<unsigned char>(code);
}

unsigned char SrgbEncoder::operator()(float linear) const {
  const float scaled = linear * scale_;
  // A curve maps first; the tables then encode its value exactly.
  return codeOfScaled(tone_ == ToneCurve::Clamp ? scaled
                                                : static_cast<float>(toneMapped(scaled, tone_)));
}

std::vector<unsigned char> SrgbEncoder::encode(const Image& image) const {
  std::vector<unsigned char> bytes;
  encodeInto(image, bytes);
  return bytes;
}

void SrgbEncoder::encodeInto(const Image& image, std::vector<unsigned char>& bytes) const {
  bytes.resize(image.pixels.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, bytes.size(), 1 << 16),
                    [&](const tbb::blocked_range<size_t>& range) {
                      const float* in = image.pixels.data();
                      if (tone_ == ToneCurve::Clamp && image.channels != 4) {
                        for (size_t i = range.begin(); i != range.end(); ++i)
                          bytes[i] = codeOfScaled(in[i] * scale_);
                        return;
                      }
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        const bool alpha = image.channels == 4 && i % 4 == 3;
                        bytes[i] = alpha ? static_cast<unsigned char>(
                                               std::lround(std::clamp(in[i], 0.0f, 1.0f) * 255))
                                         : (*this)(in[i]);
                      }
                    });
}

}  // namespace acpca
