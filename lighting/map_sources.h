#pragma once
// A lat-long map's compact bright sources (its sun, a studio's lamps), found
// and split off the map energy-exactly: each becomes a distant disc (a
// direction, an angular radius, an RGB radiance), the map keeps the rest with
// the sources' pixels filled from their surroundings (docs/lighting.md,
// "A map's sources").
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lighting/environment.h"

namespace acpca {

/// How sources are found; the defaults are what `--sun auto` uses.
struct SourceFinding {
  int maxSources = 4;        ///< K: the brightest K regions kept, the rest left in the map
  double brightFactor = 20;  ///< a pixel is bright above this many times the map's mean luminance
  double minEnergyShare =
      0.01;  ///< a region is kept holding at least this share of the map's energy
  double maxRadiusDegrees =
      4;  ///< ... and lying within this angle of its centre (about 1.4 texels at 6x32x32)
};

/// A distant disc light split off a map.
struct MapSource {
  Vec3 direction;          ///< unit, towards the source, in the map's unrotated frame
  double radius = 0;       ///< angular radius (radians) of the disc of the region's solid angle
  Rgb radiance;            ///< uniform over the disc: its energy over its solid angle
  double energyShare = 0;  ///< of the map's whole energy (luminance-weighted)
  double solidAngle() const;
  Rgb energy() const { return radiance * solidAngle(); }
  /// The same source with its direction turned, as the map it came from is.
  MapSource turned(const Eigen::Matrix3d& rotation) const;
  /// Its direction as `sun:` takes one: degrees from +Y, azimuth from -Z towards +X.
  double thetaDegrees() const;
  double phiDegrees() const;
};

/// The sources split off a map, and the map without them.
struct SplitMap {
  std::vector<MapSource> sources;  ///< brightest first
  std::vector<float> residual;     ///< the map's pixels with each source's own filled
  int width = 0, height = 0;
  LatLongPixels pixels() const { return {width, height, residual.data()}; }
};

/// An environment's sources, and what is left of it.
struct SplitEnvironment {
  std::vector<MapSource> sources;     ///< brightest first; empty: nothing split off
  std::unique_ptr<Environment> rest;  ///< the map without them (null with no sources)
};

/// Finds the bright regions (8-connected, across the u = 0/1 seam and around
/// each pole) and splits off the K brightest that are compact and hold
/// enough energy; deterministic. Each region's pixels keep min(pixel, fill)
/// in the residual, fill the mean of the dim pixels bordering the region, and
/// the source takes the rest: sources plus residual hold the map's energy.
SplitMap splitMapSources(const LatLongPixels& map, const SourceFinding& finding);

/// A built-in disc (`sun:`, the sky's sun) as a source: split off when K >= 1
/// and its angular radius is within the finding's limit; false otherwise.
bool discIsSource(double radiusRadians, const SourceFinding& finding);

/// The sources' energy share of an environment that also holds `rest`,
/// luminance-weighted: each source's energy over the sum of all of them and
/// the rest's lattice-free total (restEnergy, luminance x solid angle).
void setEnergyShares(std::vector<MapSource>& sources, double restEnergy);

/// Solid angle of pixel row `row` of a map `height` rows tall, `width` wide.
double latLongPixelSolidAngle(int row, int width, int height);

/// Direction of a map pixel's centre (docs/lighting.md, "Conventions").
Vec3 latLongPixelDirection(int x, int y, int width, int height);

/// `--sun auto|off|K`: the finding it asks for, or none (off). Refused naming
/// the parameter for anything else.
std::optional<SourceFinding> parseSourceFinding(const std::string& text);

}  // namespace acpca
