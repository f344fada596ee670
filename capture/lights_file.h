#pragma once
// Lights files of captured one-light-at-a-time (OLAT) image sets: which image
// each light made, where the light stood and what irradiance it delivered
// (docs/formats.md, "Captured transport"). JSON or CSV.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace acpca {

struct LightEntry {
  std::string image;                    ///< as the file names it (relative to the file's folder)
  std::string imagePath;                ///< resolved against the lights file's folder
  Eigen::Vector3d direction;            ///< unit, from the subject toward the light
  Eigen::Vector3d irradiance{1, 1, 1};  ///< E_k per channel, > 0
  double solidAngle = -1;               ///< the cell's, when the file gives it (else < 0)
  std::string where;                    ///< "lights.csv line 4", "lights.json: lights[3]"
};

struct LightsFile {
  std::string path;
  std::vector<LightEntry> lights;
  /// Every light's cell solid angle is given (all or none may be).
  bool cellsGiven() const { return !lights.empty() && lights.front().solidAngle >= 0; }
};

/// A light set needs at least two lights: one light's cell is the whole
/// sphere, so every relight of it would be its image scaled by the map's
/// total. Throws UserError naming `where` for fewer.
void requireLightCount(size_t lights, const std::string& where);

/// Reads a lights file: JSON when its first non-blank character is '{', else
/// CSV. Throws UserError naming the file and the line (CSV) or entry (JSON):
/// a missing or extra column, a value that is not a finite number, a zero
/// direction, a position without "center", two lights with one direction, a
/// non-positive intensity, solid angles given for some lights only, fewer
/// than two lights.
LightsFile readLightsFile(const std::string& path);

/// Warns when the folders of the listed images hold more images of their
/// kinds (extensions) than the file lists: a list that lost lines, or a
/// folder of another set.
void warnOfUnlistedImages(const LightsFile& file);

/// The same for text already in memory (fuzzing, tests); `path` names it in
/// errors and resolves the image paths.
LightsFile parseLightsFile(const std::string& text, const std::string& path);

}  // namespace acpca
