// Lat-long (equirectangular) environment images. Each source pixel is treated
// as constant radiance over its exact solid angle and split into sub-cells
// small against a texel; every sub-cell adds radiance x solid angle to the
// texel that holds its (rotated) centre (latlong_integration.h). Energy is
// conserved to rounding at any rotation, and a small sun keeps its energy.
#include <cmath>
#include <filesystem>
#include <mutex>
#include <numbers>

#include "core/error.h"
#include "core/warning.h"
#include "imageio/image_file.h"
#include "lighting/environment.h"
#include "lighting/latlong_integration.h"

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr long long kMaxPixels = 1LL << 28;  // 16k x 16k

class LatLongEnvironment : public Environment {
 public:
  LatLongEnvironment(std::string name, int width, int height, std::vector<float> rgb)
      : name_(std::move(name)),
        width_(width),
        height_(height),
        rgb_(std::move(rgb)),
        pixels_{width_, height_, rgb_.data()} {
    ACPCA_CHECK(rgb_.size() == 3ull * width * height, "lat-long buffer ", rgb_.size());
  }
  std::string name() const override { return name_; }
  const LatLongPixels* latLong() const override { return &pixels_; }

  Rgb radiance(const Vec3& dir) const override {
    const Vec3 d = dir.normalized();
    // docs/design.md section 3: u = 0.5 + atan2(x, -z) / 2 pi, v = acos(y) / pi.
    const double u = 0.5 + std::atan2(d.x(), -d.z()) / (2 * kPi);
    const double v = std::acos(std::clamp(d.y(), -1.0, 1.0)) / kPi;
    return pixels_.at(u, v);
  }

  void integrate(const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                 LatticeLighting& lighting) const override {
    if (!isYawOnly(rotation)) return integrateLatLongCells(pixels_, lattice, rotation, lighting);
    // The row sums, made on the first yaw and kept: a sweep turns one map many times.
    std::call_once(rowSumsMade_, [&] { rowSums_ = std::make_unique<LatLongRowSums>(pixels_); });
    integrateLatLongYawed(pixels_, *rowSums_, lattice, rotation, lighting);
  }

 private:
  std::string name_;
  int width_, height_;
  std::vector<float> rgb_;
  LatLongPixels pixels_;  ///< a view of rgb_
  mutable std::once_flag rowSumsMade_;
  mutable std::unique_ptr<LatLongRowSums> rowSums_;
};

}  // namespace

std::unique_ptr<Environment> makeLatLongEnvironment(std::string name, int width, int height,
                                                    std::vector<float> rgb) {
  return std::make_unique<LatLongEnvironment>(std::move(name), width, height, std::move(rgb));
}

void requireLatLongAspect(const std::string& where, int width, int height) {
  const long long twice = 2LL * height;
  if (width == twice) return;
  const double off = std::abs(width - twice) / static_cast<double>(twice);
  if (off > kLatLongAspectTolerance)
    throw UserError(concat(where, ": a ", width, "x", height,
                           " image is neither a lat-long map (2:1) nor a horizontal cube cross "
                           "(4:3); its aspect is ",
                           static_cast<double>(width) / height, ":1"));
  warn(concat(where, ": ", width, "x", height, " is not quite 2:1 (", 100 * off,
              "% off); read as a lat-long map, its texels stretched to the sphere"));
}

std::unique_ptr<Environment> makeEnvironmentFromPixels(const std::string& where, std::string name,
                                                       int width, int height, int channels,
                                                       const float* values) {
  if (width < 2 || height < 1 || static_cast<long long>(width) * height > kMaxPixels)
    throw UserError(
        concat(where, ": environment map size ", width, "x", height, " is out of range"));
  if (channels < 1) throw UserError(concat(where, ": the environment map has no channels"));
  std::vector<float> rgb(static_cast<size_t>(width) * height * 3);
  // Filtered and resampled HDRIs carry tiny negative texels (ringing); they
  // are clamped to 0, as renderers do, unless they hold a real share of the
  // map's energy. NaN and Inf are refused.
  long long negatives = 0;
  float mostNegative = 0;
  double negativeSum = 0, absoluteSum = 0;
  for (size_t p = 0; p < rgb.size() / 3; ++p)
    for (int c = 0; c < 3; ++c) {
      const float v = values[p * channels + std::min(c, channels < 3 ? 0 : c)];
      if (!std::isfinite(v))
        throw UserError(concat(where, ": pixel (", p % width, ", ", p / width, ") channel ", c,
                               " is ", v, "; radiance must be finite"));
      absoluteSum += std::abs(v);
      if (v < 0) ++negatives, negativeSum -= v, mostNegative = std::min(mostNegative, v);
      rgb[3 * p + c] = std::max(v, 0.0f);
    }
  if (negatives > 0) {
    const double share = negativeSum / absoluteSum;
    if (share > kMaxNegativeShare)
      throw UserError(concat(where, ": ", negatives, " negative values (down to ", mostNegative,
                             ") hold ", 100 * share, "% of the map's summed magnitude; more than ",
                             100 * kMaxNegativeShare, "% is not ringing but a broken map"));
    if (share > kSilentNegativeShare)
      warn(concat(where, ": ", negatives, " negative values clamped to 0 (the most negative ",
                  mostNegative, ", ", 100 * share, "% of the summed magnitude)"));
  }
  // A 4:3 image is a horizontal cube cross; lat-long maps are 2:1.
  if (width * 3 == height * 4 && width % 4 == 0)
    return makeCubeCrossEnvironment(std::move(name), width / 4, std::move(rgb));
  requireLatLongAspect(where, width, height);
  return makeLatLongEnvironment(std::move(name), width, height, std::move(rgb));
}

std::unique_ptr<Environment> loadEnvironmentImage(const std::string& path) {
  std::string error;
  auto in = openImage(path, error);
  if (!in) throw UserError(concat(path, ": cannot read the environment map: ", error));
  const ImageHeader& spec = in->header();
  if (spec.width < 2 || spec.height < 1 || spec.depth != 1 ||
      static_cast<long long>(spec.width) * spec.height > kMaxPixels)
    throw UserError(
        concat(path, ": environment map size ", spec.width, "x", spec.height, " is out of range"));
  if (spec.channels < 1) throw UserError(concat(path, ": the environment map has no channels"));
  // Only RGB (or the grey channel) is read; alpha and extra channels are skipped.
  const int channels = std::min(spec.channels, 3);
  // Even a well-compressed map needs some bytes per scanline: a header that
  // declares far more pixels than the file could hold is refused before the
  // pixel buffer is allocated.
  const double declaredBytes = double(spec.width) * spec.height * channels * sizeof(float);
  const double fileBytes = double(std::filesystem::file_size(path));
  if (declaredBytes > 4096 * fileBytes)
    throw UserError(concat(path, ": declares ", spec.width, "x", spec.height, " pixels but holds ",
                           fileBytes, " bytes (truncated or corrupt)"));
  std::vector<float> all(static_cast<size_t>(spec.width) * spec.height * channels);
  if (!in->readImage(0, channels, PixelType::Float, all.data()))
    throw UserError(concat(path, ": cannot read the environment map pixels: ", in->error()));
  return makeEnvironmentFromPixels(path, std::filesystem::path(path).stem().string(), spec.width,
                                   spec.height, channels, all.data());
}

}  // namespace acpca
