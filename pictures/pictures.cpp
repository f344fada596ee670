#include "pictures/pictures.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace acpca {

cv::Mat toneMappedBgr(const Image& image, double exposureEv) {
  const std::vector<unsigned char> rgb = SrgbEncoder(exposureEv).encode(image);
  cv::Mat mat(image.height, image.width, CV_8UC3);
  for (int y = 0; y < image.height; ++y) {
    const unsigned char* in = rgb.data() + static_cast<size_t>(y) * image.width * image.channels;
    auto* out = mat.ptr<cv::Vec3b>(y);
    for (int x = 0; x < image.width; ++x, in += image.channels) out[x] = {in[2], in[1], in[0]};
  }
  return mat;
}

std::vector<int> clusterOfPixel(const TransportHeader& header,
                                const std::vector<int>& clusterOfRow) {
  std::vector<int> out(static_cast<size_t>(header.camera.size.pixels()), -1);
  for (size_t r = 0; r < clusterOfRow.size(); ++r) out[header.pixels[r]] = clusterOfRow[r];
  return out;
}

void drawClusterBoundaries(cv::Mat& bgr, const std::vector<int>& cluster, const cv::Vec3b& colour) {
  const int w = bgr.cols, h = bgr.rows;
  auto differs = [&](int p, int q) {
    return cluster[p] >= 0 && cluster[q] >= 0 && cluster[p] != cluster[q];
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int p = y * w + x;
      if ((x + 1 < w && differs(p, p + 1)) || (y + 1 < h && differs(p, p + w)))
        bgr.at<cv::Vec3b>(y, x) = colour;
    }
}

cv::Mat errorHeatMap(const TransportHeader& header, const std::vector<float>& rowRgb,
                     const std::vector<float>& truthRgb, double scale) {
  const int w = header.camera.size.width, h = header.camera.size.height;
  double truthEnergy = 0;
  for (float v : truthRgb) truthEnergy += double(v) * v;
  const double rms = std::sqrt(truthEnergy / std::max<double>(1, header.rows()));
  cv::Mat level(h, w, CV_8UC1, cv::Scalar(0));
  std::vector<bool> occupied(static_cast<size_t>(w) * h, false);
  for (long long r = 0; r < header.rows(); ++r) {
    double e = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = double(rowRgb[3 * r + c]) - truthRgb[3 * r + c];
      e += d * d;
    }
    const double relative = rms > 0 ? std::sqrt(e) / rms : 0;
    const int p = header.pixels[r];
    level.data[p] = static_cast<unsigned char>(std::lround(255 * std::min(1.0, relative / scale)));
    occupied[p] = true;
  }
  cv::Mat colours;
  cv::applyColorMap(level, colours, cv::COLORMAP_INFERNO);
  for (int p = 0; p < w * h; ++p)
    if (!occupied[p]) colours.at<cv::Vec3b>(p / w, p % w) = {0, 0, 0};
  return colours;
}

void writePng(const cv::Mat& bgr, const std::string& path) {
  ACPCA_CHECK(bgr.type() == CV_8UC3, "a picture is 8-bit BGR");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  writePng8(rgb.cols, rgb.rows, 3, rgb.data, path);  // cvtColor allocates it whole
}

}  // namespace acpca
