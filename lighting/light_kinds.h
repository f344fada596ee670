#pragma once
// The kinds of local light, one struct each with everything a kind answers:
// its grammar, its numbers, its checks, the light it delivers at a point and
// the texels that light comes from. Code that treats lights alike calls these
// through std::visit, and the exact lamps of relight/ name every kind in an
// overload set, so a kind added to LightShape without all of them does not
// compile (docs/architecture.md, "Where new things go").
#include <array>
#include <concepts>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/vectors.h"
#include "transport/cube_lattice.h"

namespace acpca {

/// Spot lights fall smoothly to zero over this outer share of the half angle.
inline constexpr double kSpotFalloffShare = 0.1;
/// Bounds on a light's numbers: coordinates and radii, and emission, such that
/// every relit value stays finite in float.
inline constexpr double kMaxLightCoordinate = 1e15;
inline constexpr double kMaxLightEmission = 1e20;
/// A point seen closer than 1e-8 units (per unit intensity) counts as touching.
inline constexpr double kMaxIrradiancePerIntensity = 1e16;

/// A kind's grammar, written once: the parser counts numbers by it, its
/// errors quote it, and the CLI's help, Python's docstrings and
/// docs/lighting.md are made from it or checked against it.
struct LightGrammar {
  const char* kind;              ///< the name before the colon
  size_t numbersBeforeEmission;  ///< X,Y,Z and the kind's own; then I (grey) or R,G,B
  const char* grammar;
  const char* meaning;
};

/// One texel's share of a light seen from a point: the lattice lighting
/// (radiance x solid angle, per unit of the light's emission) it adds there.
struct LightTap {
  int texel = 0;
  double weight = 0;
};

/// Every kind answers these; `toLight` runs from the lit point to the light's
/// position, and its squared length is d2 > 0.
///   kGrammar, kEmission (what its emission is: "intensity" or "radiance")
///   fromNumbers(v): the kind from its own numbers (those after X,Y,Z)
///   appendNumbers(out): the same numbers back, for its canonical spec
///   problem(): what is wrong with it, or "" (may normalise, as a spot's axis)
///   reach(): no lit point may lie within this distance of it
///   irradiance(toLight): what it delivers per unit emission, -1 when the
///     point is inside it or on it
///   appendDirectionShares(lattice, toLight, taps): the texels it is seen in,
///     weights summing to 1
///   heldPointScale(): lit as a point lamp of emission x this while a viewer
///     drags it (its exact light costs many rays), or nullopt: lit as it is

/// A point light: all of it at its position.
struct PointLight {
  static constexpr LightGrammar kGrammar{
      "point", 3, "point:X,Y,Z,I or point:X,Y,Z,R,G,B",
      "a point light at X,Y,Z of radiant intensity I (or R,G,B)"};
  static constexpr const char* kEmission = "intensity";
  static PointLight fromNumbers(const double*) { return {}; }
  void appendNumbers(std::vector<double>&) const {}
  std::string problem() { return ""; }
  double reach() const { return 0; }
  double irradiance(const Vec3& toLight) const;
  void appendDirectionShares(const CubeLattice& lattice, const Vec3& toLight,
                             std::vector<LightTap>& taps) const;
  std::optional<double> heldPointScale() const { return std::nullopt; }
};

/// A sphere light of uniform surface radiance.
struct SphereLight {
  static constexpr LightGrammar kGrammar{
      "sphere", 4, "sphere:X,Y,Z,RADIUS,L or sphere:X,Y,Z,RADIUS,R,G,B",
      "a sphere of that radius whose surface has radiance L (or R,G,B)"};
  static constexpr const char* kEmission = "radiance";
  double radius = 0;

  static SphereLight fromNumbers(const double* v) { return {v[0]}; }
  void appendNumbers(std::vector<double>& out) const { out.push_back(radius); }
  std::string problem();
  double reach() const { return radius; }
  /// Its disc's exact solid angle 2 pi (1 - cos alpha).
  double irradiance(const Vec3& toLight) const;
  /// The disc's shares of the texels it covers (lighting/cap_texels.h).
  void appendDirectionShares(const CubeLattice& lattice, const Vec3& toLight,
                             std::vector<LightTap>& taps) const;
  /// The same power from its centre: L x pi r^2.
  std::optional<double> heldPointScale() const;
};

/// A spot light: a point light inside a cone that falls smoothly to zero.
struct SpotLight {
  static constexpr LightGrammar kGrammar{
      "spot", 7, "spot:X,Y,Z,DX,DY,DZ,HALF_ANGLE_DEG,I or ...,HALF_ANGLE_DEG,R,G,B",
      "a point light shining along DX,DY,DZ within HALF_ANGLE_DEG of it"};
  static constexpr const char* kEmission = "intensity";
  Vec3 axis = Vec3(0, -1, 0);    ///< unit direction the cone opens along
  double halfAngleDegrees = 45;  ///< in (0, 90]

  static SpotLight fromNumbers(const double* v) { return {Vec3(v[0], v[1], v[2]), v[3]}; }
  void appendNumbers(std::vector<double>& out) const {
    out.insert(out.end(), {axis[0], axis[1], axis[2], halfAngleDegrees});
  }
  std::string problem();
  double reach() const { return 0; }
  /// A point light's, times the falloff: 1 inside the inner cone, 0 outside
  /// the half angle, a smoothstep in the cosine over the outer
  /// kSpotFalloffShare between.
  double irradiance(const Vec3& toLight) const;
  void appendDirectionShares(const CubeLattice& lattice, const Vec3& toLight,
                             std::vector<LightTap>& taps) const;
  std::optional<double> heldPointScale() const { return std::nullopt; }
};

/// The kind of a light, and what only it has.
using LightShape = std::variant<PointLight, SphereLight, SpotLight>;

/// What every kind answers (the list above): a kind added to LightShape
/// without one of them fails the static_assert below.
template <typename Kind>
concept LightKind = requires(Kind kind, const Kind& seen, const Vec3& toLight,
                             const CubeLattice& lattice, std::vector<LightTap>& taps,
                             std::vector<double>& numbers, const double* v) {
  { Kind::kGrammar } -> std::convertible_to<LightGrammar>;
  { Kind::kEmission } -> std::convertible_to<const char*>;
  { Kind::fromNumbers(v) } -> std::same_as<Kind>;
  seen.appendNumbers(numbers);
  { kind.problem() } -> std::same_as<std::string>;
  { seen.reach() } -> std::same_as<double>;
  { seen.irradiance(toLight) } -> std::same_as<double>;
  seen.appendDirectionShares(lattice, toLight, taps);
  { seen.heldPointScale() } -> std::same_as<std::optional<double>>;
};
static_assert([]<size_t... K>(std::index_sequence<K...>) {
  return (LightKind<std::variant_alternative_t<K, LightShape>> && ...);
}(std::make_index_sequence<std::variant_size_v<LightShape>>()));

/// Every kind's grammar, in LightShape's order.
inline constexpr auto kLightGrammars = []<size_t... K>(std::index_sequence<K...>) {
  return std::array<LightGrammar, sizeof...(K)>{
      std::variant_alternative_t<K, LightShape>::kGrammar...};
}
(std::make_index_sequence<std::variant_size_v<LightShape>>());

/// The index in LightShape (and kLightGrammars) of the kind named `name`;
/// nullopt for a name that is no kind.
std::optional<size_t> lightKindNamed(const std::string& name);
/// Kind `kind` made from its own numbers `v` (as many as its grammar says).
LightShape lightShapeFrom(size_t kind, const double* v);
/// The kinds' names, "point, sphere, spot" (errors).
std::string lightKindList();

}  // namespace acpca
