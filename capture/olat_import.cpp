#include "capture/olat_import.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/half.h"
#include "core/resources.h"
#include "core/stopwatch.h"
#include "core/warning.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

/// Bytes of one band of every image: bands of about this size keep memory
/// flat while each read is long enough to stream.
constexpr size_t kBandBytes = size_t{256} << 20;
/// Rows handed to the writer at once.
constexpr long long kWriteRows = 1024;

/// The rows of the covered pixels, kept as the file will store them, in pixel order.
class KeptRows {
 public:
  /// At most maxRows rows: their room is reserved once (address space only
  /// until rows arrive), so growing never holds two copies at once.
  KeptRows(int rowLength, Precision precision, long long maxRows)
      : length_(rowLength), half_(precision == Precision::F16) {
    const size_t values = static_cast<size_t>(maxRows) * rowLength;
    if (half_)
      halves_.reserve(values);
    else
      floats_.reserve(values);
  }
  void add(const float* row) {
    if (half_) {
      const size_t at = halves_.size();
      halves_.resize(at + length_);
      floatToHalf(row, halves_.data() + at, length_);
    } else {
      floats_.insert(floats_.end(), row, row + length_);
    }
  }
  /// Rows [first, first + count), the first `keep` values of each, as floats.
  void read(long long first, long long count, int keep, float* out) const {
    for (long long i = 0; i < count; ++i) {
      const size_t at = static_cast<size_t>(first + i) * length_;
      if (half_)
        halfToFloat(halves_.data() + at, out + i * keep, keep);
      else
        std::copy_n(floats_.data() + at, keep, out + i * keep);
    }
  }

 private:
  int length_;
  bool half_;
  std::vector<std::uint16_t> halves_;
  std::vector<float> floats_;
};

/// What the bands found beyond the rows themselves.
struct BandTally {
  bool grey = true;         ///< every row's R, G and B equal
  long long negatives = 0;  ///< values below 0, clamped
  long long overHalf = 0;   ///< values an f16 file cannot hold
};

/// Pixel p of the band as one row, R values of every light, then G, then B:
/// each image's value over its light's irradiance and over the pixel's
/// coverage. Images hold a partly covered pixel premultiplied (over
/// black, as renderers and EXR store it), while a relight multiplies the row
/// by the coverage when it composes the frame.
void pixelRow(const std::vector<float>& band, size_t perImage, size_t p, float coverage,
              const OlatLights& lights, float* row, BandTally& tally) {
  const int n = static_cast<int>(lights.directions.size());
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) {
      float v =
          band[k * perImage + 3 * p + c] / static_cast<float>(lights.irradiance[k][c] * coverage);
      if (v < 0) ++tally.negatives, v = 0;
      if (v > kHalfMax) ++tally.overHalf;
      row[c * n + k] = v;
    }
  for (int k = 0; k < n && tally.grey; ++k)
    tally.grey = row[k] == row[n + k] && row[k] == row[2 * n + k];
}

void checkLights(const OlatImages& images, const OlatLights& lights) {
  const size_t n = lights.directions.size();
  if (static_cast<size_t>(images.count()) != n)
    throw UserError(concat(images.count(), " images for ", n, " lights: give one image per light"));
  if (lights.irradiance.size() != n ||
      (!lights.solidAngles.empty() && lights.solidAngles.size() != n))
    throw UserError(concat(n, " directions, ", lights.irradiance.size(), " intensities and ",
                           lights.solidAngles.size(), " solid angles: give one of each per light"));
  for (size_t k = 0; k < n; ++k) {
    if (!lights.directions[k].allFinite() || std::abs(lights.directions[k].norm() - 1) > 1e-9)
      throw UserError(concat("directions[", k, "] is not a unit vector"));
    if (!lights.irradiance[k].allFinite() || !(lights.irradiance[k].array() > 0).all())
      throw UserError(concat("intensities[", k, "] must be > 0 in every channel"));
  }
  const auto [first, second] = findSameDirection(lights.directions);
  if (second >= 0)
    throw UserError(concat("directions[", second, "] is the same as directions[", first,
                           "] (two lights cannot stand in one place)"));
}

void warnOfTally(const BandTally& tally, long long saturated, int saturatedImages,
                 const OlatImportOptions& o) {
  if (saturated > 0)
    warn(concat(saturated, " values in ", saturatedImages,
                " images sit at the top of their range (saturated): the relit image is too dark "
                "there"));
  if (tally.negatives > 0) warn(concat(tally.negatives, " negative values clamped to 0"));
  if (tally.overHalf > 0 && o.precision == Precision::F16)
    warn(concat(tally.overHalf, " values exceed ", kHalfMax,
                ", the largest an f16 file holds: they are clamped (--precision f32 keeps them)"));
}

}  // namespace

nlohmann::json importReport(const OlatImportResult& r, const std::string& out) {
  const TransportHeader& h = r.header;
  return {{"out", out},
          {"lights", h.lights.size()},
          {"width", h.camera.size.width},
          {"height", h.camera.size.height},
          {"occupied_pixels", h.rows()},
          {"channels", h.channels},
          {"cells", h.lights.describe()},
          {"uncovered_sr", h.lights.uncoveredSolidAngle()},
          {"saturated_values", r.saturatedValues},
          {"saturated_images", r.saturatedImages},
          {"bytes", r.bytesWritten},
          {"seconds", r.seconds}};
}

LightSet makeLightSet(const OlatLights& lights, double capDegrees) {
  LightSet set;
  set.directions = lights.directions;
  set.irradiance = lights.irradiance;
  if (!lights.solidAngles.empty()) {
    set.cells = CellSource::Given;
    set.solidAngles = lights.solidAngles;
  } else {
    set.cells = CellSource::CappedVoronoi;
    set.capDegrees = capDegrees > 0 ? capDegrees : defaultCellCapDegrees(lights.directions);
    if (!(set.capDegrees > 0 && set.capDegrees <= 180))
      throw ParameterError("cell cap", set.capDegrees, "must be in (0, 180] degrees");
    set.solidAngles = LightCells(lights.directions, set.capDegrees).solidAngles();
  }
  set.validate("the light set");
  return set;
}

OlatImportResult importOlat(OlatImages& images, const OlatLights& lights,
                            const OlatImportOptions& o) {
  const Stopwatch watch;
  checkLights(images, lights);
  const int n = images.count();
  const ImageSize size = images.size();
  OlatImportResult result;
  TransportHeader& h = result.header;
  h.camera.size = size;
  h.cubemapResolution = 0;
  h.lights = makeLightSet(lights, o.capDegrees);
  h.precision = o.precision;
  h.scene = o.name;
  const std::vector<float> mask = o.mask.empty() ? std::vector<float>{} : readMask(o.mask, size);

  // Every pixel may be covered: its rows held until the file is written.
  const long long rowsBytes = size.pixels() * 3LL * n * (o.precision == Precision::F16 ? 2 : 4);
  ResourceNeed need;
  need.what = concat("a transport of ", n, " images of ", size.width, "x", size.height);
  need.memoryBytes = rowsBytes + static_cast<long long>(kBandBytes);
  need.diskBytes = need.largestFile = rowsBytes;
  need.diskDirectory = fs::absolute(o.out).parent_path().string();
  need.memoryAdvice = "import fewer lights or smaller images, or give a --mask";
  need.diskAdvice = "write the transport to another disk";
  requireResources(need, o.force);

  const size_t rowBytes = static_cast<size_t>(size.width) * 3 * sizeof(float);
  const int bandRows = static_cast<int>(
      std::clamp<size_t>(kBandBytes / (rowBytes * n), 1, static_cast<size_t>(size.height)));
  const size_t perImage = static_cast<size_t>(bandRows) * size.width * 3;
  std::vector<float> band(perImage * n), row(3 * static_cast<size_t>(n));
  KeptRows kept(3 * n, o.precision, size.pixels());
  BandTally tally;
  for (int y0 = 0; y0 < size.height; y0 += bandRows) {
    const int y1 = std::min(size.height, y0 + bandRows);
    tbb::parallel_for(0, n, [&](int k) { images.readBand(k, y0, y1, band.data() + k * perImage); });
    for (size_t p = 0; p < static_cast<size_t>(y1 - y0) * size.width; ++p) {
      const long long pixel = static_cast<long long>(y0) * size.width + static_cast<long long>(p);
      float coverage = 1;
      if (!mask.empty()) {
        coverage = mask[pixel];
      } else {
        bool lit = false;
        for (int k = 0; k < n && !lit; ++k)
          for (int c = 0; c < 3; ++c) lit = lit || band[k * perImage + 3 * p + c] > 0;
        coverage = lit ? 1.0f : 0.0f;
      }
      if (!(coverage > 0)) continue;
      pixelRow(band, perImage, p, coverage, lights, row.data(), tally);
      kept.add(row.data());
      h.pixels.push_back(static_cast<std::int32_t>(pixel));
      h.coverage.push_back(coverage);
    }
    if (o.progress) o.progress(y1, size.height);
  }
  if (h.pixels.empty())
    throw UserError(o.mask.empty() ? "every image is black at every pixel: nothing to import"
                                   : concat(o.mask, ": the mask covers no pixel"));
  long long saturated = 0;
  for (int k = 0; k < n; ++k) {
    saturated += images.saturated(k);
    result.saturatedImages += images.saturated(k) > 0;
  }
  result.saturatedValues = saturated;
  warnOfTally(tally, saturated, result.saturatedImages, o);

  // Grey images (every channel equal after calibration) keep one row per
  // pixel: the colour is the lighting's alone.
  h.channels = tally.grey ? 1 : 3;
  h.albedo.assign(3 * h.pixels.size(), 1.0f);
  TransportWriter writer(o.out, h);
  const int keep = h.rowLength();
  std::vector<float> block(static_cast<size_t>(kWriteRows) * keep);
  for (long long first = 0; first < h.rows(); first += kWriteRows) {
    const long long count = std::min(kWriteRows, h.rows() - first);
    kept.read(first, count, keep, block.data());
    writer.writeRows(first, count, block.data());
  }
  writer.finish();
  result.bytesWritten = writer.bytesWritten();
  result.seconds = watch.seconds();
  return result;
}

}  // namespace acpca
