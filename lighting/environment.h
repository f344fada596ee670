#pragma once
// Environment lighting: analytic maps (constant, sun, sky) and lat-long images,
// integrated onto the cube lattice by area, never point-sampled, so that a small
// sun keeps its energy at every resolution and rotation (docs/design.md section 3).
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/vectors.h"
#include "transport/camera.h"
#include "transport/cube_lattice.h"

namespace acpca {

/// Per-texel lighting on the lattice: RGB radiance integrated over each texel's
/// solid angle (radiance x dOmega), laid out [texel * 3 + channel].
using LatticeLighting = std::vector<double>;

struct SourceFinding;     // lighting/map_sources.h
struct SplitEnvironment;  // lighting/map_sources.h

/// A lat-long map's pixels, looked up by (u, v) = (0.5 + atan2(x, -z) / 2 pi,
/// acos(y) / pi) (docs/lighting.md, "Conventions").
struct LatLongPixels {
  int width = 0, height = 0;
  const float* rgb = nullptr;  ///< width x height x 3, row 0 at +Y
  /// Bilinear between pixel centres, wrapping in u (any real u) and clamping
  /// in v: what the map's radiance() gives. Inline: a frame's background
  /// looks up every pixel that shows the map.
  Rgb at(double u, double v) const;
};

inline Rgb LatLongPixels::at(double u, double v) const {
  // Bilinear between pixel centres, wrapping in u and clamping in v; the
  // four taps summed in this order, in doubles, component by component.
  const double x = u * width - 0.5, y = std::clamp(v * height - 0.5, 0.0, height - 1.0);
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  // Wrap in u; x0 and x0 + 1 lie in [-1, width] but at the seam (or past it
  // for a shifted u), so the divisions of the general wrap are rarely needed.
  const auto wrap = [&](int px) {
    return px >= 0 && px < width ? px : (px % width + width) % width;
  };
  const int px[2] = {wrap(x0), wrap(x0 + 1)};
  const int py[2] = {y0, std::min(y0 + 1, height - 1)};
  double sum[3] = {0, 0, 0};
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      const double w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
      const float* p = rgb + 3 * (static_cast<size_t>(py[dy]) * width + px[dx]);
      for (int c = 0; c < 3; ++c) sum[c] += w * p[c];
    }
  return {sum[0], sum[1], sum[2]};
}

class Environment {
 public:
  virtual ~Environment() = default;
  /// A lat-long map's pixels (null for any other environment): a camera's
  /// background turned by a yaw is a shift in u (relight/image_composer.h).
  virtual const LatLongPixels* latLong() const { return nullptr; }
  /// Short name for output files and manifests ("sky", "sun_50_30_4_1000", file stem).
  virtual std::string name() const = 0;
  /// Radiance arriving from unit direction d, of the unrotated map.
  virtual Rgb radiance(const Vec3& d) const = 0;
  /// Adds, for every texel j, the integral of the rotated map's radiance over the
  /// texel: integral over texel j of L(R^T w) dw. Total energy is conserved.
  virtual void integrate(const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                         LatticeLighting& lighting) const = 0;
  /// integrate() under each of `rotations`, onto *lightings[k]: the same
  /// values, each on a task of its own unless the map can do better (a
  /// large lat-long map reads each row once for several yaws). Thread-safe
  /// integrate() assumed, as for every environment here.
  virtual void integrateMany(const CubeLattice& lattice,
                             const std::vector<Eigen::Matrix3d>& rotations,
                             const std::vector<LatticeLighting*>& lightings) const;
  /// The map's compact bright sources split off as distant discs, and the
  /// map without them (lighting/map_sources.h, docs/lighting.md "A map's
  /// sources"): a lat-long map's found regions, a built-in sun. None, and
  /// no map, where nothing is split off (the default).
  virtual SplitEnvironment splitSources(const SourceFinding& finding) const;
};

/// A built-in map's grammar, written once: loadEnvironment parses by it, its
/// errors quote it, and the CLI's help, Python's docstrings and
/// docs/lighting.md are made from it or checked against it.
struct EnvironmentGrammar {
  const char* prefix;   ///< what a spec starts with ("sky" is the whole spec)
  const char* grammar;  ///< the spec written out
  const char* meaning;
};
inline constexpr std::array<EnvironmentGrammar, 3> kEnvironmentGrammars{{
    {"constant:", "constant:V or constant:R,G,B", "uniform radiance from every direction"},
    {"sun:", "sun:THETA,PHI,SIZE_DEG,INTENSITY",
     "a disc SIZE_DEG across of radiance INTENSITY, THETA from +Y, PHI from -Z towards +X"},
    {"sky", "sky", "the built-in sun and sky"},
}};
/// The built-in maps' grammars joined ("constant:V or constant:R,G,B,
/// sun:..., sky"), for help texts and messages.
std::string environmentGrammarList();

/// Parses an ENV argument: a built-in map (kEnvironmentGrammars) or an image
/// file (lat-long or cube cross, anything OpenImageIO reads). Throws
/// ParameterError ("environment") or UserError naming the argument.
std::unique_ptr<Environment> loadEnvironment(const std::string& spec);
/// Negative values are ringing from filtering when they hold at most this share
/// of a map's summed magnitude (all channels): they are clamped to 0, with a
/// warning above kSilentNegativeShare. Debian's blender-data world maps hold up
/// to 6e-7, which no relit value can show (below half an f16 step).
inline constexpr double kMaxNegativeShare = 0.01;
inline constexpr double kSilentNegativeShare = 1e-6;

/// Loads an environment image (OpenImageIO): RGB, finite; tiny negative values
/// clamped (kMaxNegativeShare); a horizontal cube cross when its aspect is 4:3,
/// a lat-long map when it is 2:1 (requireLatLongAspect), else refused.
std::unique_ptr<Environment> loadEnvironmentImage(const std::string& path);
/// True if spec names an analytic map rather than a file.
bool isAnalyticEnvironment(const std::string& spec);

/// The extensions (lower case) of the files a directory of maps gives.
inline constexpr std::array<std::string_view, 5> kMapFileExtensions{".exr", ".hdr", ".pfm", ".tif",
                                                                    ".tiff"};
/// Lighting specs with each directory replaced by the lighting images it holds
/// (kMapFileExtensions, any case; sorted); analytic specs and files pass through.
/// Throws ParameterError for a directory without any.
std::vector<std::string> expandEnvironmentSpecs(const std::vector<std::string>& specs);

std::unique_ptr<Environment> makeConstantEnvironment(const Rgb& radiance);
/// A disc of angular diameter sizeDegrees and uniform radiance, centred at the
/// lat-long angles theta (from +Y) and phi (0 towards -Z, 90 towards +X).
std::unique_ptr<Environment> makeSunEnvironment(double thetaDegrees, double phiDegrees,
                                                double sizeDegrees, const Rgb& radiance);
/// The built-in sun-and-sky (docs/lighting.md).
std::unique_ptr<Environment> makeSkyEnvironment();
/// A horizontal cube cross (4 x 3 faces of faceSize pixels, the layout of
/// latticeToCross), RGB row-major.
std::unique_ptr<Environment> makeCubeCrossEnvironment(std::string name, int faceSize,
                                                      std::vector<float> rgb);
/// A lat-long image in memory: width x height RGB, row 0 at the zenith.
std::unique_ptr<Environment> makeLatLongEnvironment(std::string name, int width, int height,
                                                    std::vector<float> rgb);
/// A lat-long map's width within this share of twice its height is read with a
/// warning (a map cropped or padded by a pixel); further off, it is refused.
inline constexpr double kLatLongAspectTolerance = 0.01;
/// Refuses (UserError naming `where` and the size) an image that is not a
/// 2:1 lat-long map within kLatLongAspectTolerance; warns when not exactly.
void requireLatLongAspect(const std::string& where, int width, int height);
/// An environment image in memory, checked and read as loadEnvironmentImage
/// reads a file: width x height pixels of `channels` floats (1: grey; beyond 3
/// ignored), row 0 at the top. `where` names it in errors and warnings.
std::unique_ptr<Environment> makeEnvironmentFromPixels(const std::string& where, std::string name,
                                                       int width, int height, int channels,
                                                       const float* values);

/// Integrates a smooth radiance function over every texel by splitting the texel
/// into sub x sub cells weighted by their exact solid angles (for analytic maps).
void integrateSmoothFunction(const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                             const std::function<Rgb(const Vec3&)>& radiance, int sub,
                             LatticeLighting& lighting);

}  // namespace acpca
