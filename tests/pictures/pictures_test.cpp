// The shared pictures: PNGs hold the canvas's pixels (BGR on screen, RGB in
// the file), tone mapping is the one PNG output uses, cluster boundaries mark
// exactly the pixels next to another cluster, and heat maps leave the
// background black.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>

#include "core/srgb.h"
#include "pictures/pictures.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

std::vector<unsigned char> readRgb(const std::string& path, int& width, int& height) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  if (!in) return {};
  width = in->spec().width, height = in->spec().height;
  EXPECT_EQ(in->spec().nchannels, 3);
  std::vector<unsigned char> rgb(static_cast<size_t>(width) * height * 3);
  EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data()));
  return rgb;
}

TEST(Pictures, APngHoldsTheCanvasPixelsInRgbOrder) {
  test::TempDir dir;
  cv::Mat bgr(3, 5, CV_8UC3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      bgr.at<cv::Vec3b>(y, x) = {static_cast<unsigned char>(10 * x), static_cast<unsigned char>(y),
                                 static_cast<unsigned char>(200 + x + y)};
  writePng(bgr, dir.file("p.png"));
  int w = 0, h = 0;
  const auto rgb = readRgb(dir.file("p.png"), w, h);
  ASSERT_EQ(w, 5);
  ASSERT_EQ(h, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      const size_t i = (static_cast<size_t>(y) * 5 + x) * 3;
      EXPECT_EQ(rgb[i], 200 + x + y);
      EXPECT_EQ(rgb[i + 1], y);
      EXPECT_EQ(rgb[i + 2], 10 * x);
    }
  EXPECT_THROW(writePng(bgr, dir.file("missing/p.png")), UserError);
}

TEST(Pictures, ToneMappingIsThePngEncoding) {
  Image image{2, 1, 3, {0.0f, 0.18f, 1.0f, 0.5f, 2.0f, 0.001f}};
  const cv::Mat bgr = toneMappedBgr(image, 0);
  for (int x = 0; x < 2; ++x)
    for (int c = 0; c < 3; ++c) {
      const double v = std::min(1.0f, image.pixels[x * 3 + c]);
      EXPECT_EQ(bgr.at<cv::Vec3b>(0, x)[2 - c], std::lround(255 * linearToSrgb(v)));
    }
}

TEST(Pictures, BoundariesMarkPixelsBesideAnotherClusterAndNotTheBackground) {
  // Two clusters side by side over a 4x2 image, background at the right end.
  const std::vector<int> cluster{0, 0, 1, -1, 0, 0, 1, -1};
  cv::Mat bgr(2, 4, CV_8UC3, cv::Scalar(0, 0, 0));
  drawClusterBoundaries(bgr, cluster, {255, 255, 255});
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const bool marked = bgr.at<cv::Vec3b>(y, x)[0] == 255;
      EXPECT_EQ(marked, x == 1) << x << "," << y;  // only the left cluster's edge
    }
}

}  // namespace
}  // namespace acpca
