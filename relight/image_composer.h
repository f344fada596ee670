#pragma once
// Relit images composed: per-pixel results over the background (the map, black
// or transparent), straight into an image buffer.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "imageio/image.h"
#include "lighting/environment.h"
#include "transport/transport_file.h"

namespace acpca {

enum class Background { Env, Black, Alpha };
inline constexpr EnumNames<Background, 3> kBackgroundNames{
    "background",
    {{{Background::Env, "env"}, {Background::Black, "black"}, {Background::Alpha, "alpha"}}}};
Background parseBackground(const std::string& text);  // env | black | alpha
/// Refuses Background::Env for a captured light set, which has no camera to
/// see the environment through: a ParameterError naming "background" and `path`.
void requireBackgroundShown(const TransportHeader& header, Background background,
                            const std::string& path);

/// What clamping a frame at zero changed (docs/design.md, section 6): a
/// model's reconstruction undershoots where the transport is zero or small,
/// and no surface emits negative light.
struct NegativeClamp {
  long long values = 0;    ///< colour values that were below zero
  float mostNegative = 0;  ///< the lowest of them (0 when none)
  void add(const NegativeClamp& other) {
    values += other.values;
    mostNegative = std::min(mostNegative, other.mostNegative);
  }
};
/// Raises every negative colour value of an image of `channels` floats per
/// pixel to 0 (the alpha of 4 channels is coverage, never negative) and says
/// what changed; `keep` counts them and changes nothing.
NegativeClamp clampNegative(float* pixels, size_t values, int channels, bool keep = false);

/// Places per-row RGB (albedo applied) into the image. Background pixels (and
/// the uncovered part of silhouette pixels) show the rotated environment, black,
/// or transparency (RGBA, alpha = coverage).
Image composeImage(const TransportHeader& header, const std::vector<float>& rowRgb,
                   Background background, const Environment& env, const Eigen::Matrix3d& rotation);
/// The same into `pixels`: width x height x channels floats (4 with Alpha,
/// else 3), every value written.
void composeInto(const TransportHeader& header, const float* rowRgb, Background background,
                 const Environment& env, const Eigen::Matrix3d& rotation, float* pixels);

/// Composes the frames of one camera (the coverage image is built once): the
/// background first, then each occupied pixel's relit value added, from rows
/// (addRows) or straight from the relighter (ModelRelighter::relightInto).
/// Keeps its own copy of what it needs from the header.
class ImageComposer {
 public:
  explicit ImageComposer(const TransportHeader& header);
  static int channels(Background background) { return background == Background::Alpha ? 4 : 3; }
  /// Every pixel's background part: (1 - coverage) x the environment seen
  /// through it (Env) or 0, and alpha = coverage (Alpha). `silhouettesOnly`:
  /// the environment only where an object covers part of the pixel (what a
  /// frame's shading takes away), 0 at pure background.
  void background(Background background, const Environment& env, const Eigen::Matrix3d& rotation,
                  float* pixels, bool silhouettesOnly = false) const;
  /// Adds coverage x rowRgb (3 floats per row) at each row's pixel.
  void addRows(const float* rowRgb, float* pixels, int channels) const;

 private:
  Camera camera_;
  std::vector<std::int32_t> rowPixels_;  ///< pixel of each row
  std::vector<float> rowCoverage_;       ///< coverage of each row
  std::vector<float> coverage_;          ///< per pixel, 0 for background
  /// Pixels with coverage below 1 (row by row), and the camera ray through each.
  std::vector<size_t> backgroundPixel_, backgroundRowStart_;
  std::vector<Vec3> backgroundRay_;
  /// Each background ray's lat-long (u, v) (docs/lighting.md): under a yaw
  /// alone a lat-long map is looked up at (u + yaw / 2 pi, v), no atan2 or
  /// acos per pixel and frame.
  std::vector<double> backgroundU_, backgroundV_;
};

}  // namespace acpca
