// Lat-long (equirectangular) environment images. Each source pixel is treated
// as constant radiance over its exact solid angle and split into sub-cells
// small against a texel; every sub-cell adds radiance x solid angle to the
// texel that holds its (rotated) centre (latlong_integration.h). Energy is
// conserved to rounding at any rotation, and a small sun keeps its energy.
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>
#include <numbers>

#include "core/error.h"
#include "core/warning.h"
#include "imageio/image_file.h"
#include "lighting/builtin_maps.h"
#include "lighting/environment.h"
#include "lighting/latlong_integration.h"
#include "lighting/map_sources.h"

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;
/// Maps up to this size are integrated one yaw at a time (integrateMany).
constexpr long long kCachedPixels = 1LL << 20;

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
    integrateLatLongYawed(pixels_, rowSums(), lattice, rotation, lighting);
  }

  void integrateMany(const CubeLattice& lattice, const std::vector<Eigen::Matrix3d>& rotations,
                     const std::vector<LatticeLighting*>& lightings) const override {
    // A map of up to a million pixels stays in cache from one yaw to the
    // next, and one yaw at a time is then faster (docs/results.md).
    const bool yaws = std::all_of(rotations.begin(), rotations.end(), isYawOnly);
    if (!yaws || rotations.size() < 2 || static_cast<long long>(width_) * height_ <= kCachedPixels)
      return Environment::integrateMany(lattice, rotations, lightings);
    integrateLatLongYaws(pixels_, rowSums(), lattice, rotations, lightings);
  }

  SplitEnvironment splitSources(const SourceFinding& finding) const override {
    SplitMap split = splitMapSources(pixels_, finding);
    SplitEnvironment out;
    if (split.sources.empty()) return out;
    out.sources = std::move(split.sources);
    out.rest = makeLatLongEnvironment(name_, width_, height_, std::move(split.residual));
    return out;
  }

 private:
  std::string name_;
  int width_, height_;
  std::vector<float> rgb_;
  LatLongPixels pixels_;  ///< a view of rgb_
  /// The row sums, made on the first yaw and kept: a sweep turns one map
  /// many times. Isolated: while this thread waits on the sums' rows it
  /// runs none of a caller's other tasks, which could come back to this flag.
  const LatLongRowSums& rowSums() const {
    std::call_once(rowSumsMade_, [&] {
      tbb::this_task_arena::isolate([&] { rowSums_ = std::make_unique<LatLongRowSums>(pixels_); });
    });
    return *rowSums_;
  }

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

namespace {

/// One row of a map's values: whether all are finite (and the first that is
/// not), and what its negative values hold against the row's magnitude.
struct RowRadiance {
  long long firstBad = -1;  ///< the first non-finite value's index in the row
  long long negatives = 0;
  float mostNegative = 0;
  double negativeSum = 0, absoluteSum = 0;
};

/// Checks a row of values and clamps its negatives to 0 in place. Eight
/// lanes of sums side by side: the compiler keeps them in vector registers.
RowRadiance clampRow(float* v, size_t n) {
  constexpr size_t kLanes = 8;
  double absolute[kLanes] = {}, negative[kLanes] = {};
  long long count[kLanes] = {};
  float most[kLanes] = {};
  bool bad[kLanes] = {};
  size_t i = 0;
  const auto add = [&](size_t j, float x) {
    bad[j] |= !(std::abs(x) <= std::numeric_limits<float>::max());  // NaN compares false
    absolute[j] += std::abs(static_cast<double>(x));
    negative[j] += static_cast<double>(std::max(-x, 0.0f));
    count[j] += x < 0;
    most[j] = std::min(most[j], x);
  };
  for (; i + kLanes <= n; i += kLanes)
    for (size_t j = 0; j < kLanes; ++j) add(j, v[i + j]);
  for (size_t j = 0; i + j < n; ++j) add(j, v[i + j]);
  RowRadiance row;
  for (size_t j = 0; j < kLanes; ++j) {
    if (bad[j]) row.firstBad = 0;
    row.absoluteSum += absolute[j], row.negativeSum += negative[j];
    row.negatives += count[j], row.mostNegative = std::min(row.mostNegative, most[j]);
  }
  if (row.firstBad >= 0) {  // named before anything is clamped
    while (std::abs(v[row.firstBad]) <= std::numeric_limits<float>::max()) ++row.firstBad;
    return row;
  }
  if (row.negatives > 0)
    for (size_t k = 0; k < n; ++k) v[k] = std::max(v[k], 0.0f);
  return row;
}

/// A map's RGB values checked and clamped in place, rows on all cores, the
/// rows' sums added in order (the same result for any thread count).
/// Filtered and resampled HDRIs carry tiny negative texels (ringing); they
/// are clamped to 0, as renderers do, unless they hold a real share of the
/// map's energy. NaN and Inf are refused.
void requireMapRadiance(const std::string& where, int width, int height, std::vector<float>& rgb) {
  const size_t rowValues = 3 * static_cast<size_t>(width);
  std::vector<RowRadiance> rows(height);
  tbb::parallel_for(0, height, [&](int y) { rows[y] = clampRow(&rgb[y * rowValues], rowValues); });
  RowRadiance all;
  for (int y = 0; y < height; ++y) {
    const RowRadiance& row = rows[y];
    if (row.firstBad >= 0) {
      const long long p = static_cast<long long>(y) * width + row.firstBad / 3;
      throw UserError(concat(where, ": pixel (", p % width, ", ", p / width, ") channel ",
                             row.firstBad % 3, " is ", rgb[y * rowValues + row.firstBad],
                             "; radiance must be finite"));
    }
    all.absoluteSum += row.absoluteSum, all.negativeSum += row.negativeSum;
    all.negatives += row.negatives, all.mostNegative = std::min(all.mostNegative, row.mostNegative);
  }
  if (all.negatives == 0) return;
  const double share = all.negativeSum / all.absoluteSum;
  if (share > kMaxNegativeShare)
    throw UserError(concat(where, ": ", all.negatives, " negative values (down to ",
                           all.mostNegative, ") hold ", 100 * share,
                           "% of the map's summed magnitude; more than ", 100 * kMaxNegativeShare,
                           "% is not ringing but a broken map"));
  if (share > kSilentNegativeShare)
    warn(concat(where, ": ", all.negatives, " negative values clamped to 0 (the most negative ",
                all.mostNegative, ", ", 100 * share, "% of the summed magnitude)"));
}

/// An environment from RGB values already in place: checked, then a cube
/// cross or a lat-long map by its aspect.
std::unique_ptr<Environment> makeEnvironmentFromRgb(const std::string& where, std::string name,
                                                    int width, int height, std::vector<float> rgb) {
  requireMapRadiance(where, width, height, rgb);
  // A 4:3 image is a horizontal cube cross; lat-long maps are 2:1.
  if (width * 3 == height * 4 && width % 4 == 0)
    return makeCubeCrossEnvironment(std::move(name), width / 4, std::move(rgb));
  requireLatLongAspect(where, width, height);
  return makeLatLongEnvironment(std::move(name), width, height, std::move(rgb));
}

/// Values of `channels` a pixel as RGB: grey repeated, beyond 3 dropped.
std::vector<float> rgbOf(const float* values, size_t pixels, int channels) {
  std::vector<float> rgb(pixels * 3);
  for (size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c)
      rgb[3 * p + c] = values[p * channels + std::min(c, channels < 3 ? 0 : c)];
  return rgb;
}

}  // namespace

std::unique_ptr<Environment> makeEnvironmentFromPixels(const std::string& where, std::string name,
                                                       int width, int height, int channels,
                                                       const float* values) {
  if (width < 2 || height < 1 || static_cast<long long>(width) * height > kMaxMapPixels)
    throw UserError(
        concat(where, ": environment map size ", width, "x", height, " is out of range"));
  if (channels < 1) throw UserError(concat(where, ": the environment map has no channels"));
  return makeEnvironmentFromRgb(where, std::move(name), width, height,
                                rgbOf(values, static_cast<size_t>(width) * height, channels));
}

std::unique_ptr<Environment> loadEnvironmentImage(const std::string& path) {
  std::string error;
  auto in = openImage(path, error);
  if (!in) throw UserError(concat(path, ": cannot read the environment map: ", error));
  const ImageHeader& spec = in->header();
  if (spec.width < 2 || spec.height < 1 || spec.depth != 1 ||
      static_cast<long long>(spec.width) * spec.height > kMaxMapPixels)
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
  // RGB files are checked where they were read: no second copy of the map.
  std::vector<float> rgb =
      channels == 3 ? std::move(all) : rgbOf(all.data(), all.size() / channels, channels);
  return makeEnvironmentFromRgb(path, std::filesystem::path(path).stem().string(), spec.width,
                                spec.height, std::move(rgb));
}

}  // namespace acpca
