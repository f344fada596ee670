#pragma once
// Local lights: point, sphere and spot lights at world positions, seen from
// each pixel's position as a sparse lattice lighting (docs/lighting.md,
// "Local lights"). Visibility in the transport was traced to infinity, so a
// local light is exact only where nothing lies between it and infinity along
// each pixel's ray to it.
#include <optional>
#include <string>
#include <vector>

#include "lighting/environment.h"
#include "lighting/light_kinds.h"

namespace acpca {

/// Every kind's grammar, one per line (help texts and docstrings).
std::string lightGrammarLines(const std::string& indent = "  ");

struct LocalLight {
  LightShape shape;  ///< the kind, and what only it has
  Vec3 position = Vec3::Zero();
  /// Point and spot: radiant intensity per channel (a diffuse plane of albedo
  /// a facing it at distance d shows a I / (pi d^2)). Sphere: the uniform
  /// radiance of its surface (the same plane shows a L (radius / d)^2).
  Rgb emission = Rgb::Ones();
  std::string spec;  ///< the text it came from (messages, manifests)

  /// Its kind's name, as its spec starts.
  const char* kindName() const { return kLightGrammars[shape.index()].kind; }
  /// What only kind `Kind` has, or nullptr for a light of another kind.
  template <typename Kind>
  const Kind* as() const {
    return std::get_if<Kind>(&shape);
  }
  /// The light as the CLI grammar writes it (point:X,Y,Z,R,G,B, ...).
  std::string canonicalSpec() const;
};

/// Parses a light by kLightGrammars. Throws ParameterError ("light") naming the spec and what is
/// wrong.
LocalLight parseLocalLight(const std::string& spec);
/// Whether a spec sweeps one of its numbers: A:B:S in its place.
bool isLightSweep(const std::string& spec);
/// The most numbers a light has (a spot with RGB intensity).
inline constexpr size_t kMaxLightNumbers = 10;
/// The most specs one sweep may give.
inline constexpr long long kMaxLightSweepSpecs = 100000;
/// A spec whose numbers may be sweeps A:B:S (A, A + S, ... below B, as
/// --rotate sweeps the yaw) as one spec per combination, the last swept
/// number fastest, each number written as the shortest text that reads
/// back the same; a spec without sweeps as itself. Throws ParameterError
/// ("light") naming the spec for an unknown kind, a number that is not
/// one, more than kMaxLightNumbers numbers, a step <= 0, an end not past
/// the start or more than kMaxLightSweepSpecs specs (how many numbers the
/// kind takes is checked when the specs are parsed).
std::vector<std::string> expandLightSweep(const std::string& spec);
/// A light path (--light-path): one frame's lights per line, specs separated
/// by spaces or ';'; blank lines and lines starting with '#' are skipped.
/// Throws UserError naming the file and line.
std::vector<std::vector<LocalLight>> readLightPath(const std::string& path);

/// Checks a light built in code (Python) as the parser checks text:
/// finite values, emission >= 0, and its kind's own checks (a radius > 0, a
/// non-zero spot axis, normalised here, a half angle in (0, 90]). Throws
/// ParameterError ("light").
void validateLocalLight(LocalLight& light);
/// The light lit as a point lamp of the same power while a viewer drags it
/// (a sphere's exact light costs many rays), or nullopt: lit as it is.
std::optional<LocalLight> heldAsPoint(const LocalLight& light);

/// What a light adds to the lattice lighting at `point`, per unit emission,
/// appended to `taps` (texels may repeat). A point or spot light: its
/// irradiance 1/d^2 (times the spot's falloff) over the four texels nearest
/// its direction with bilinear weights, so it moves smoothly across texels. A
/// sphere: its disc's exact solid angle 2 pi (1 - cos alpha), split over the
/// texels it covers in proportion to the covered solid angle. Returns false
/// when the point lies inside the sphere or on the point light (taps untouched).
bool appendLightTaps(const LocalLight& light, const CubeLattice& lattice, const Vec3& point,
                     std::vector<LightTap>& taps);

/// What appendLightTaps splits into: the irradiance a light delivers at
/// `point` per unit emission (1/d^2 times a spot's falloff; a sphere's solid
/// angle), or -1 when the point is inside the sphere or on the point light...
double lightIrradiance(const LocalLight& light, const Vec3& point);
/// ...and the texels it comes from, with weights summing to 1 (bilinear for
/// point and spot, the disc's shares for a sphere); false as above.
bool appendDirectionTaps(const LocalLight& light, const CubeLattice& lattice, const Vec3& point,
                         std::vector<LightTap>& taps);

/// The lights as they are seen from one point, summed into a lattice lighting
/// (3 values per texel, as environments give): the whole lighting of a pixel.
LatticeLighting localLighting(const std::vector<LocalLight>& lights, const CubeLattice& lattice,
                              const Vec3& point);

}  // namespace acpca
