#include "relight/image_composer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "lighting/latlong_integration.h"

namespace acpca {

Background parseBackground(const std::string& text) {
  return kBackgroundNames.parse(text);
}

void requireBackgroundShown(const TransportHeader& header, Background background,
                            const std::string& path) {
  if (header.isLightSet() && background == Background::Env)
    throw ParameterError("background", "env",
                         concat(path,
                                " is a captured light set: no camera sees the environment "
                                "behind it (use black or alpha)"));
}

NegativeClamp clampNegative(float* pixels, size_t values, int channels, bool keep) {
  NegativeClamp clamp;
  // Without branches, so a frame's millions of values vectorize: a value not
  // >= 0 (negative or NaN) is counted and, unless kept, becomes 0.
  const auto visit = [&](float& v) {
    const bool below = !(v >= 0);
    clamp.values += below;
    clamp.mostNegative = v < clamp.mostNegative ? v : clamp.mostNegative;
    if (!keep) v = below ? 0.0f : v;
  };
  if (channels != 4) {
    for (size_t i = 0; i < values; ++i) visit(pixels[i]);
    return clamp;
  }
  // Alpha (the fourth of four channels) is coverage: never negative, skipped.
  for (size_t p = 0; p + 3 < values; p += 4)
    for (size_t c = 0; c < 3; ++c) visit(pixels[p + c]);
  return clamp;
}

Image composeImage(const TransportHeader& header, const std::vector<float>& rowRgb,
                   Background background, const Environment& env, const Eigen::Matrix3d& rotation) {
  Image image;
  image.width = header.camera.size.width;
  image.height = header.camera.size.height;
  image.channels = background == Background::Alpha ? 4 : 3;
  image.pixels.resize(static_cast<size_t>(image.width) * image.height * image.channels);
  composeInto(header, rowRgb.data(), background, env, rotation, image.pixels.data());
  return image;
}

void composeInto(const TransportHeader& header, const float* rowRgb, Background background,
                 const Environment& env, const Eigen::Matrix3d& rotation, float* pixels) {
  const ImageComposer composer(header);
  composer.background(background, env, rotation, pixels);
  composer.addRows(rowRgb, pixels, ImageComposer::channels(background));
}

ImageComposer::ImageComposer(const TransportHeader& header)
    : camera_(header.camera),
      rowPixels_(header.pixels),
      rowCoverage_(header.coverage),
      coverage_(static_cast<size_t>(header.camera.size.pixels()), 0.0f) {
  for (long long r = 0; r < header.rows(); ++r) coverage_[header.pixels[r]] = header.coverage[r];
  // The pixels that show some environment, and their camera rays.
  const int width = camera_.size.width, height = camera_.size.height;
  backgroundRowStart_.push_back(0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t pixel = static_cast<size_t>(y) * width + x;
      if (coverage_[pixel] >= 1) continue;
      backgroundPixel_.push_back(pixel);
      backgroundRay_.push_back(camera_.rayDirection(x + 0.5, y + 0.5));
      // As LatLongEnvironment::radiance finds them.
      const Vec3 d = backgroundRay_.back().normalized();
      backgroundU_.push_back(0.5 + std::atan2(d.x(), -d.z()) / (2 * std::numbers::pi));
      backgroundV_.push_back(std::acos(std::clamp(d.y(), -1.0, 1.0)) / std::numbers::pi);
    }
    backgroundRowStart_.push_back(backgroundPixel_.size());
  }
}

void ImageComposer::background(Background background, const Environment& env,
                               const Eigen::Matrix3d& rotation, float* pixels,
                               bool silhouettesOnly) const {
  const Camera& camera = camera_;
  const int width = camera.size.width, height = camera.size.height;
  const int channels = ImageComposer::channels(background);
  const Eigen::Matrix3d inverse = rotation.transpose();
  // A lat-long map turned by a yaw alone (R = Ry(yaw), as --rotate YAW and
  // yaw sweeps make it): the map slides along u, so each pixel's (u, v) is
  // found once per view. R^T d has atan2(x, -z) larger by the yaw.
  const LatLongPixels* map = env.latLong();
  const bool yawOnly = map && isYawOnly(rotation);
  const double shift = std::atan2(rotation(0, 2), rotation(0, 0)) / (2 * std::numbers::pi);
  // Rows in parallel, each pixel written once: 0 (and alpha) where the
  // environment does not show, else the environment through the camera ray
  // worked out once (backgroundRay_), the costly part. A frame's buffer may
  // hold the last frame's values: nothing is read before it is written.
  const bool shown = background == Background::Env, alpha = background == Background::Alpha;
  tbb::parallel_for(0, height, [&](int y) {
    size_t next = backgroundRowStart_[y];
    const size_t end = backgroundRowStart_[y + 1];
    for (int x = 0; x < width; ++x) {
      const size_t pixel = static_cast<size_t>(y) * width + x;
      float* out = pixels + pixel * channels;
      const float cov = coverage_[pixel];
      if (alpha) out[3] = cov;
      const bool shows = next < end && backgroundPixel_[next] == pixel;
      if (!shows || !shown || (silhouettesOnly && cov == 0)) {
        out[0] = out[1] = out[2] = 0;
        next += shows;
        continue;
      }
      const Rgb bg = yawOnly ? map->at(backgroundU_[next] + shift, backgroundV_[next])
                             : env.radiance(inverse * backgroundRay_[next]);
      for (int c = 0; c < 3; ++c) out[c] = float((1 - cov) * bg[c]);
      ++next;
    }
  });
}

void ImageComposer::addRows(const float* rowRgb, float* pixels, int channels) const {
  // Each row has its own pixel: rows in parallel write disjoint values.
  const long long rows = static_cast<long long>(rowPixels_.size());
  tbb::parallel_for(tbb::blocked_range<long long>(0, rows, 4096),
                    [&](const tbb::blocked_range<long long>& range) {
                      for (long long r = range.begin(); r != range.end(); ++r) {
                        float* out = pixels + static_cast<size_t>(rowPixels_[r]) * channels;
                        for (int c = 0; c < 3; ++c) out[c] += rowCoverage_[r] * rowRgb[3 * r + c];
                      }
                    });
}

}  // namespace acpca
