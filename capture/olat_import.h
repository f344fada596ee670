#pragma once
// Captured light transport: a one-light-at-a-time image set and its lights
// made into a transport file over a light set (docs/formats.md, "Captured
// transport"). Row p holds pixel p's value in every image k divided by the
// irradiance E_k its light delivered, so the relit image under lighting
// Phi_k (the environment integrated over light k's cell) is sum_k I_k Phi_k / E_k.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "capture/olat_images.h"
#include "transport/transport_file.h"

namespace acpca {

struct OlatImportOptions {
  std::string out;
  /// Coverage image (see readMask); empty: a pixel is covered when some
  /// image is not black there.
  std::string mask;
  Precision precision = Precision::F16;
  /// Cells' cap in degrees; 0: defaultCellCapDegrees of the directions.
  double capDegrees = 0;
  /// What the file's "scene" attribute says it is (the lights file's name).
  std::string name;
  /// Import even when the rows may not fit memory or the disk (they are
  /// checked before any image is read, for every pixel covered).
  bool force = false;
  std::function<void(long long done, long long total)> progress;  ///< image rows read
};

/// The lights of a set: directions (unit), irradiance E_k (> 0 per channel)
/// and, optionally, each cell's solid angle (empty: capped Voronoi cells).
struct OlatLights {
  std::vector<Vec3> directions;
  std::vector<Eigen::Vector3d> irradiance;
  std::vector<double> solidAngles;
};

struct OlatImportResult {
  TransportHeader header;  ///< as written, rows aside
  long long saturatedValues = 0;
  int saturatedImages = 0;
  long long bytesWritten = 0;
  double seconds = 0;
};

/// What an import made, as `import --json` and Python report it (without
/// the process's peak memory, which the caller adds).
nlohmann::json importReport(const OlatImportResult& result, const std::string& out);

/// The light set's cells: given, or capped Voronoi cells of the directions.
LightSet makeLightSet(const OlatLights& lights, double capDegrees);

/// Reads every image in bands and writes the transport file (nothing
/// appears under `out` unless it all succeeds). Throws UserError naming the
/// image or option at fault; warns of saturated values.
OlatImportResult importOlat(OlatImages& images, const OlatLights& lights,
                            const OlatImportOptions& options);

}  // namespace acpca
