// The sRGB encoders the PNG writers and the viewer share: they must give the
// very codes of the formulas round(255 or 65535 * srgb(v * 2^EV)) for every value.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>

#include <OpenImageIO/imageio.h>

#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/srgb.h"
#include "imageio/image_output.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

unsigned char formula(float v, double exposureEv) {
  const float scaled = v * static_cast<float>(std::exp2(exposureEv));
  return static_cast<unsigned char>(std::lround(linearToSrgb(scaled) * 255));
}

TEST(SrgbEncoder, GivesTheFormulasCodeForEveryValueTried) {
  for (double ev : {-3.0, 0.0, 1.5, 7.25}) {
    const SrgbEncoder encode(ev);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> logValue(-12, 4);
    for (int i = 0; i < 200000; ++i) {
      const float v = std::exp2(logValue(rng)) * (ev > 0 ? std::exp2(float(-ev)) : 1.0f);
      ASSERT_EQ(encode(v), formula(v, ev)) << "v = " << v << " at EV " << ev;
    }
    // Around every step of the code, one float either side.
    for (int b = 1; b < 256; ++b) {
      float lo = 0, hi = 1;
      for (int k = 0; k < 60; ++k) {
        const float mid = 0.5f * (lo + hi);
        (formula(mid, 0) >= b ? hi : lo) = mid;
      }
      for (float v : {std::nextafter(hi, 0.0f), hi, std::nextafter(hi, 2.0f)})
        EXPECT_EQ(SrgbEncoder(0)(v), formula(v, 0)) << v;
    }
  }
  const SrgbEncoder encode(0);
  EXPECT_EQ(encode(-1.0f), 0);
  EXPECT_EQ(encode(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(encode(1e30f), 255);
  EXPECT_EQ(encode(std::numeric_limits<float>::infinity()), 255);
}

TEST(SrgbEncoder, AWholeImageGivesTheFormulasCodeForEveryFloatTried) {
  // Every float in [0, 1] when ACPCA_EXHAUSTIVE is set (1.07e9 values), else
  // every 97th, through encodeInto (the batch's path), at EV 0 and -1.
  const std::uint32_t stride = std::getenv("ACPCA_EXHAUSTIVE") ? 1 : 97;
  const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
  for (double ev : {0.0, -1.0}) {
    const SrgbEncoder encode(ev);
    Image image;
    std::vector<unsigned char> bytes;
    long long mismatches = 0;
    const std::uint64_t span = std::uint64_t(stride) << 20;  // an image of 2^20 values at a time
    for (std::uint64_t first = 0; first <= one; first += span) {
      image.pixels.clear();
      for (std::uint64_t bits = first; bits < first + span && bits <= one; bits += stride)
        image.pixels.push_back(std::bit_cast<float>(static_cast<std::uint32_t>(bits)));
      while (image.pixels.size() % 3) image.pixels.push_back(0.0f);
      image.width = static_cast<int>(image.pixels.size() / 3);
      image.height = 1;
      encode.encodeInto(image, bytes);
      for (size_t i = 0; i < bytes.size(); ++i)
        mismatches += bytes[i] != formula(image.pixels[i], ev);
    }
    EXPECT_EQ(mismatches, 0) << "EV " << ev;
  }
}

std::uint16_t formula16(float v, double exposureEv, ToneCurve tone = ToneCurve::Clamp) {
  const double curve = toneMapped(double(v) * std::exp2(exposureEv), tone);
  return static_cast<std::uint16_t>(std::lround(linearToSrgb(curve) * 65535));
}

TEST(Srgb16Encoder, GivesTheFormulasCodeForEveryValueTried) {
  // Every float in [0, 1] at EV 0 when ACPCA_EXHAUSTIVE is set (1.07e9
  // values), else every 97th; random values at other exposures and ACES;
  // one double either side of every step.
  const Srgb16Encoder encode0(0);
  const std::uint32_t stride = std::getenv("ACPCA_EXHAUSTIVE") ? 1 : 97;
  const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
  long long mismatches = 0;
  for (std::uint32_t bits = 0; bits <= one; bits += stride) {
    const float v = std::bit_cast<float>(bits);
    mismatches += encode0(v) != formula16(v, 0);
  }
  EXPECT_EQ(mismatches, 0);
  for (const ToneCurve tone : {ToneCurve::Clamp, ToneCurve::Aces})
    for (double ev : {-3.0, 0.0, 1.5, 7.25}) {
      const Srgb16Encoder encode(ev, tone);
      std::mt19937 rng(7);
      std::uniform_real_distribution<float> logValue(-20, 4);
      for (int i = 0; i < 200000; ++i) {
        const float v = std::exp2(logValue(rng)) * (ev > 0 ? std::exp2(float(-ev)) : 1.0f);
        ASSERT_EQ(encode(v), formula16(v, ev, tone)) << "v = " << v << " at EV " << ev;
      }
    }
  for (int c = 1; c < 65536; c += 7) {  // the steps, as curve values: EV 0 keeps them exact
    double lo = 0, hi = 1;
    for (int k = 0; k < 70; ++k) {
      const double mid = 0.5 * (lo + hi);
      (std::lround(linearToSrgb(mid) * 65535) >= c ? hi : lo) = mid;
    }
    for (double v : {std::nextafter(hi, 0.0), hi, std::nextafter(hi, 2.0)}) {
      const float f = static_cast<float>(v);
      EXPECT_EQ(encode0(f), formula16(f, 0)) << v;
    }
  }
  EXPECT_EQ(encode0(-1.0f), 0);
  EXPECT_EQ(encode0(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(encode0(1e30f), 65535);
  EXPECT_EQ(encode0(std::numeric_limits<float>::infinity()), 65535);
}

TEST(SrgbEncoder, LeavesAlphaAsCoverage) {
  Image image;
  image.width = 2;
  image.height = 1;
  image.channels = 4;
  image.pixels = {0.5f, 0.25f, 2.0f, 0.5f, 0.0f, 1.0f, 0.01f, 1.0f};
  const auto bytes = SrgbEncoder(1).encode(image);
  EXPECT_EQ(bytes[3], 128);  // alpha 0.5, not tone mapped or scaled
  EXPECT_EQ(bytes[7], 255);
  EXPECT_EQ(bytes[0], formula(0.5f, 1));
  EXPECT_EQ(bytes[6], formula(0.01f, 1));
}

TEST(ToneCurve, AcesIsNarkowiczsFitClampedAndMonotone) {
  EXPECT_EQ(toneMapped(0, ToneCurve::Aces), 0);
  EXPECT_NEAR(toneMapped(1, ToneCurve::Aces), 2.54 / 3.16, 1e-15);  // 0.8038
  // Middle grey: 0.18 (0.4818) / (0.18 (1.0274) + 0.14) = 0.086724 / 0.324932.
  EXPECT_NEAR(toneMapped(0.18, ToneCurve::Aces), 0.266899, 1e-6);
  EXPECT_EQ(toneMapped(100, ToneCurve::Aces), 1);
  EXPECT_EQ(toneMapped(-1, ToneCurve::Aces), 0);
  EXPECT_EQ(toneMapped(0.5, ToneCurve::Clamp), 0.5);
  EXPECT_EQ(toneMapped(2, ToneCurve::Clamp), 1);
  double last = 0;
  for (double v = 0; v < 20; v += 0.01) {
    const double t = toneMapped(v, ToneCurve::Aces);
    ASSERT_GE(t, last) << v;
    last = t;
  }
  // The 8-bit encoder through the curve: the formula's code.
  const SrgbEncoder encode(1, ToneCurve::Aces);
  for (float v : {0.001f, 0.09f, 0.5f, 3.0f, 40.0f})
    EXPECT_EQ(encode(v), std::lround(255 * linearToSrgb(toneMapped(2.0 * v, ToneCurve::Aces))))
        << v;
}

TEST(ImageFormats, SixteenBitPngAndNpyHoldTheValuesAsTheyShould) {
  test::TempDir dir;
  Image image{3, 1, 3, {0.0f, 0.25f, 0.5f, 0.5f, 1.0f, 4.0f, 0.0031308f, 0.125f, 2.0f}};
  const std::string png = dir.file("a.png"), npy = dir.file("a.npy");
  encodeImage(image, png, png, ImageFormat::Png16, 1, ImageEncoding{});
  auto in = OIIO::ImageInput::open(png);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT16);
  std::vector<std::uint16_t> codes(9);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT16, codes.data()));
  // x 2^1, then sRGB: 0.5 -> 1.0 and 0.25 -> 0.5, whose sRGB value is
  // 0.735357 (188 of 255 in 8 bits): 48191.6 of 65535.
  EXPECT_EQ(codes[0], 0);
  EXPECT_EQ(codes[1], 48192);
  EXPECT_EQ(codes[2], 65535);
  EXPECT_EQ(codes[5], 65535);  // clamped
  // 0.0031308 x 2 is past the linear toe: 1.055 (0.0062616)^(1/2.4) - 0.055.
  EXPECT_EQ(codes[6], std::lround(65535 * (1.055 * std::pow(0.0062616, 1 / 2.4) - 0.055)));
  encodeImage(image, npy, npy, ImageFormat::Npy, 1, ImageEncoding{});
  std::ifstream file(npy, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find("'shape': (1, 3, 3)"), std::string::npos);
  ASSERT_GE(bytes.size(), 36u);
  float last[9];
  std::memcpy(last, bytes.data() + bytes.size() - 36, 36);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(last[i], 2 * image.pixels[i]) << i;  // linear, x 2^1
}

TEST(ImageOutput, PngIsSrgbEncodedAndWritesAreAtomic) {
  EXPECT_NEAR(linearToSrgb(0.0), 0.0, 1e-12);
  EXPECT_NEAR(linearToSrgb(1.0), 1.0, 1e-12);
  EXPECT_NEAR(linearToSrgb(0.18), 0.4614, 1e-3);
  test::TempDir dir;
  Image image{4, 2, 3, std::vector<float>(24, 0.5f)};
  EXPECT_THROW(writeImage(image, dir.file("no/dir/x.png"), ImageFormat::Png, 0), UserError);
  writeImage(image, dir.file("x.exr"), ImageFormat::Exr, 1.0);
  writeImage(image, dir.file("x.png"), ImageFormat::Png, 0);
  int files = 0;
  for (const auto& e : test::fs::directory_iterator(dir.path())) {
    ++files;
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos);
  }
  EXPECT_EQ(files, 2);
}

}  // namespace
}  // namespace acpca
