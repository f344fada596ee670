#include "lighting/map_sources.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"

namespace acpca {

namespace {

constexpr double kPi = 3.14159265358979323846;

double luminance(const float* p) {
  return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}
double luminance(const Rgb& c) {
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

/// Calls visit(index) for each of pixel (x, y)'s eight neighbours: wrapping
/// in u, and past a pole onto the same row half way round.
template <typename Visit>
void forNeighbours(int x, int y, int width, int height, Visit visit) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;
      int nx = x + dx, ny = y + dy;
      if (ny < 0 || ny >= height) ny = ny < 0 ? 0 : height - 1, nx += width / 2;
      nx = (nx % width + width) % width;
      visit(static_cast<long long>(ny) * width + nx);
    }
}

/// A bright region: its pixels, and what splitting it off would take.
struct Region {
  std::vector<long long> pixels;  ///< in the order found
  float fill[3] = {0, 0, 0};      ///< what its pixels keep at most
  Rgb excess = Rgb::Zero();       ///< sum of (pixel - kept) x solid angle
  Vec3 centre = Vec3::Zero();
  double solidAngle = 0, extent = 0;
  double peak = 0;  ///< the largest luminance taken per unit solid angle, pixel by pixel
};

/// The region of bright pixels holding `seed`, marked 2 in `state`.
std::vector<long long> growRegion(long long seed, int width, int height,
                                  std::vector<unsigned char>& state) {
  std::vector<long long> pixels{seed};
  state[seed] = 2;
  for (size_t k = 0; k < pixels.size(); ++k)
    forNeighbours(int(pixels[k] % width), int(pixels[k] / width), width, height, [&](long long n) {
      if (state[n] == 1) state[n] = 2, pixels.push_back(n);
    });
  return pixels;
}

/// A region's fill (the mean of the dim pixels bordering it, by solid angle),
/// the excess over it, the centre (weighted by the excess's luminance) and
/// the extent (docs/lighting.md, "A map's sources").
void measureRegion(const LatLongPixels& map, const std::vector<unsigned char>& state, Region& r) {
  const int w = map.width, h = map.height;
  std::vector<long long> border;
  for (long long p : r.pixels)
    forNeighbours(int(p % w), int(p / w), w, h, [&](long long n) {
      if (state[n] == 0) border.push_back(n);
    });
  std::sort(border.begin(), border.end());
  border.erase(std::unique(border.begin(), border.end()), border.end());
  Rgb fill = Rgb::Zero();
  double weight = 0;
  for (long long n : border) {
    const double omega = latLongPixelSolidAngle(int(n / w), w, h);
    for (int c = 0; c < 3; ++c) fill[c] += omega * map.rgb[3 * n + c];
    weight += omega;
  }
  for (int c = 0; c < 3; ++c) r.fill[c] = weight > 0 ? static_cast<float>(fill[c] / weight) : 0.f;
  for (long long p : r.pixels) {
    const double omega = latLongPixelSolidAngle(int(p / w), w, h);
    Rgb taken;
    for (int c = 0; c < 3; ++c)
      taken[c] = double(map.rgb[3 * p + c]) - double(std::min(map.rgb[3 * p + c], r.fill[c]));
    r.excess += omega * taken;
    r.solidAngle += omega;
    r.peak = std::max(r.peak, luminance(taken));
    r.centre += omega * luminance(taken) * latLongPixelDirection(int(p % w), int(p / w), w, h);
  }
  if (r.centre.squaredNorm() == 0) return;
  r.centre.normalize();
  // The farthest pixel centre, plus half a pixel's height.
  for (long long p : r.pixels) {
    const Vec3 d = latLongPixelDirection(int(p % w), int(p / w), w, h);
    r.extent = std::max(r.extent, std::acos(std::clamp(d.dot(r.centre), -1.0, 1.0)));
  }
  r.extent += 0.5 * kPi / h;
}

}  // namespace

SplitEnvironment Environment::splitSources(const SourceFinding&) const {
  return {};
}

bool discIsSource(double radiusRadians, const SourceFinding& finding) {
  return finding.maxSources >= 1 && radiusRadians <= finding.maxRadiusDegrees * kPi / 180;
}

void setEnergyShares(std::vector<MapSource>& sources, double restEnergy) {
  double total = restEnergy;
  for (const MapSource& s : sources) total += luminance(s.energy());
  for (MapSource& s : sources) s.energyShare = total > 0 ? luminance(s.energy()) / total : 0;
}

double MapSource::solidAngle() const {
  return 2 * kPi * (1 - std::cos(radius));
}

MapSource MapSource::turned(const Eigen::Matrix3d& rotation) const {
  MapSource s = *this;
  s.direction = rotation * direction;
  return s;
}

double MapSource::thetaDegrees() const {
  return std::acos(std::clamp(direction[1], -1.0, 1.0)) * (180 / kPi);
}

double MapSource::phiDegrees() const {
  return std::atan2(direction[0], -direction[2]) * (180 / kPi);
}

double latLongPixelSolidAngle(int row, int width, int height) {
  return (std::cos(kPi * row / height) - std::cos(kPi * (row + 1) / height)) * 2 * kPi / width;
}

Vec3 latLongPixelDirection(int x, int y, int width, int height) {
  const double theta = kPi * (y + 0.5) / height, phi = 2 * kPi * ((x + 0.5) / width - 0.5);
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

SplitMap splitMapSources(const LatLongPixels& map, const SourceFinding& f) {
  const int w = map.width, h = map.height;
  const long long count = static_cast<long long>(w) * h;
  SplitMap out;
  out.width = w, out.height = h;
  out.residual.assign(map.rgb, map.rgb + 3 * count);
  double energy = 0;
  for (int y = 0; y < h; ++y) {
    double row = 0;
    for (int x = 0; x < w; ++x) row += luminance(map.rgb + 3 * (static_cast<long long>(y) * w + x));
    energy += row * latLongPixelSolidAngle(y, w, h);
  }
  if (!(energy > 0) || f.maxSources < 1) return out;
  // 0 dim, 1 bright, 2 bright and in a region found.
  const double threshold = f.brightFactor * energy / (4 * kPi);
  std::vector<unsigned char> state(count);
  for (long long p = 0; p < count; ++p) state[p] = luminance(map.rgb + 3 * p) > threshold;
  std::vector<Region> kept;
  for (long long p = 0; p < count; ++p) {
    if (state[p] != 1) continue;
    Region r;
    r.pixels = growRegion(p, w, h, state);
    measureRegion(map, state, r);
    if (luminance(r.excess) >= f.minEnergyShare * energy &&
        r.extent <= f.maxRadiusDegrees * kPi / 180)
      kept.push_back(std::move(r));
  }
  // Brightest first; regions are found in scan order, so ties keep it.
  std::stable_sort(kept.begin(), kept.end(), [](const Region& a, const Region& b) {
    return luminance(a.excess) > luminance(b.excess);
  });
  if (static_cast<int>(kept.size()) > f.maxSources) kept.resize(f.maxSources);
  for (const Region& r : kept) {
    for (long long p : r.pixels)
      for (int c = 0; c < 3; ++c) out.residual[3 * p + c] = std::min(map.rgb[3 * p + c], r.fill[c]);
    MapSource s;
    s.direction = r.centre;
    // The disc of the region's peak radiance that holds its energy: pixels
    // the disc's rim covers in part count by what they hold, not whole.
    const double omega = std::min(r.solidAngle, luminance(r.excess) / r.peak);
    s.radius = std::acos(1 - omega / (2 * kPi));
    s.radiance = r.excess / omega;
    s.energyShare = luminance(r.excess) / energy;
    out.sources.push_back(s);
  }
  return out;
}

std::optional<SourceFinding> parseSourceFinding(const std::string& text) {
  if (text == "auto") return SourceFinding{};
  if (text == "off") return std::nullopt;
  const bool digits =
      !text.empty() && text.size() <= 3 &&
      std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!digits || std::stoi(text) < 1)
    throw ParameterError("sources", text, "must be auto, off or a count of sources (1 to 999)");
  SourceFinding finding;
  finding.maxSources = std::stoi(text);
  return finding;
}

}  // namespace acpca
