#include "lighting/light_kinds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "lighting/cap_texels.h"
#include "lighting/spec_parsing.h"

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;

/// The inverse square law per unit intensity, or -1 on the point.
double inverseSquare(const Vec3& toLight) {
  const double d2 = toLight.squaredNorm();
  const double irradiance = 1 / d2;
  return d2 > 0 && irradiance <= kMaxIrradiancePerIntensity ? irradiance : -1;
}

/// A point's direction shares: bilinear over the four nearest texels, so it
/// moves smoothly across them.
void appendBilinearShares(const CubeLattice& lattice, const Vec3& toLight,
                          std::vector<LightTap>& taps) {
  for (const BilinearTap& tap : lattice.bilinearTaps(toLight))
    if (tap.weight != 0) taps.push_back({tap.texel, tap.weight});
}

/// Kind K of LightShape made from its numbers.
template <size_t K>
LightShape shapeOf(const double* v) {
  return std::variant_alternative_t<K, LightShape>::fromNumbers(v);
}

/// Each kind's maker, in LightShape's order.
using ShapeMaker = LightShape (*)(const double*);
constexpr auto kShapeMakers = []<size_t... K>(std::index_sequence<K...>) {
  return std::array<ShapeMaker, sizeof...(K)>{&shapeOf<K>...};
}
(std::make_index_sequence<std::variant_size_v<LightShape>>());

}  // namespace

double PointLight::irradiance(const Vec3& toLight) const {
  return inverseSquare(toLight);
}

void PointLight::appendDirectionShares(const CubeLattice& lattice, const Vec3& toLight,
                                       std::vector<LightTap>& taps) const {
  appendBilinearShares(lattice, toLight, taps);
}

std::string SphereLight::problem() {
  return radius > 0 && radius <= kMaxLightCoordinate
             ? ""
             : concat("its radius must be finite and in (0, ", kMaxLightCoordinate, "]");
}

double SphereLight::irradiance(const Vec3& toLight) const {
  const double d2 = toLight.squaredNorm();
  if (!(d2 > radius * radius)) return -1;
  // 2 pi (1 - cos alpha) with sin alpha = radius / d, without cancellation.
  const double sinAlpha = radius / std::sqrt(d2);
  const double cosAlpha = std::sqrt(std::max(0.0, 1 - sinAlpha * sinAlpha));
  return 2 * kPi * sinAlpha * sinAlpha / (1 + cosAlpha);
}

void SphereLight::appendDirectionShares(const CubeLattice& lattice, const Vec3& toLight,
                                        std::vector<LightTap>& taps) const {
  const double d = std::sqrt(toLight.squaredNorm());
  appendCapShares(lattice, toLight / d, radius / d, taps);
}

std::optional<double> SphereLight::heldPointScale() const {
  return kPi * radius * radius;
}

std::string SpotLight::problem() {
  if (!axis.allFinite() || !(axis.norm() > 0))
    return "its direction DX,DY,DZ is zero or not finite";
  // Normalised once: a spec that holds a unit axis reads back unchanged.
  if (std::abs(axis.squaredNorm() - 1) > 4 * std::numeric_limits<double>::epsilon())
    axis.normalize();
  if (!(halfAngleDegrees > 0 && halfAngleDegrees <= 90))
    return "its half angle must be in (0, 90] degrees";
  return "";
}

double SpotLight::irradiance(const Vec3& toLight) const {
  const double irradiance = inverseSquare(toLight);
  if (irradiance < 0) return irradiance;
  const Vec3 fromLight = -toLight / std::sqrt(toLight.squaredNorm());
  const double half = halfAngleDegrees * kPi / 180;
  const double cosOuter = std::cos(half), cosInner = std::cos((1 - kSpotFalloffShare) * half);
  const double t = std::clamp((axis.dot(fromLight) - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
  return irradiance * (t * t * (3 - 2 * t));
}

void SpotLight::appendDirectionShares(const CubeLattice& lattice, const Vec3& toLight,
                                      std::vector<LightTap>& taps) const {
  appendBilinearShares(lattice, toLight, taps);
}

std::optional<size_t> lightKindNamed(const std::string& name) {
  for (size_t k = 0; k < kLightGrammars.size(); ++k)
    if (name == kLightGrammars[k].kind) return k;
  return std::nullopt;
}

LightShape lightShapeFrom(size_t kind, const double* v) {
  return kShapeMakers.at(kind)(v);
}

std::string lightKindList() {
  std::string list;
  for (const LightGrammar& g : kLightGrammars)
    list += (list.empty() ? "" : ", ") + std::string(g.kind);
  return list;
}

}  // namespace acpca
