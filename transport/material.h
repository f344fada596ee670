#pragma once
// Materials separate into an RGB albedo times a scalar "shape" (docs/design.md
// section 3), so each occupied pixel has exactly one transport row.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/enum_names.h"
#include "transport/cube_lattice.h"

namespace acpca {

struct Material {
  enum class Type { Diffuse, Phong, Ggx };
  Type type = Type::Diffuse;
  Eigen::Vector3f albedo{0.5f, 0.5f, 0.5f};
  double specular = 0.0;   ///< Phong's and GGX's ks in [0, 1]: the specular share of the albedo
  double exponent = 1.0;   ///< Phong s >= 0
  double roughness = 0.5;  ///< GGX alpha in [kMinRoughness, 1]
};
/// A material's "type" in scene JSON.
inline constexpr EnumNames<Material::Type, 3> kMaterialTypeNames{
    "material type",
    {{{Material::Type::Diffuse, "diffuse"},
      {Material::Type::Phong, "phong"},
      {Material::Type::Ggx, "ggx"}}}};

/// Rec. 709 luminance of a linear RGB value: weighs albedos inside a pixel.
inline float luminance(const Eigen::Vector3f& rgb) {
  return 0.2126f * rgb.x() + 0.7152f * rgb.y() + 0.0722f * rgb.z();
}

/// Below this GGX is a mirror no lattice resolves.
inline constexpr double kMinRoughness = 1e-3;

/// GGX (Trowbridge-Reitz) distribution of microfacet normals at cos(n, h):
/// alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2); integrates to 1 against n.h.
template <typename T>
T ggxDistribution(T cosH, T alpha) {
  const T a2 = alpha * alpha, d = cosH * cosH * (a2 - 1) + 1;
  return a2 / (T(std::numbers::pi) * d * d);
}

/// Smith's Lambda for GGX at a direction cos(theta) from the normal.
template <typename T>
T ggxLambda(T cosTheta, T alpha) {
  const T c2 = cosTheta * cosTheta, tan2 = std::max(T(0), 1 - c2) / c2;
  return (std::sqrt(1 + alpha * alpha * tan2) - 1) / 2;
}

/// The GGX specular term without Fresnel, D G2 / (4 cos_i cos_o), with the
/// height-correlated Smith masking-shadowing G2 = 1 / (1 + Lambda_i + Lambda_o);
/// 0 unless both directions are above the surface. Symmetric in i and o.
template <typename T>
T ggxSpecular(T cosI, T cosO, T cosH, T alpha) {
  if (cosI <= 0 || cosO <= 0 || cosH <= 0) return 0;
  const T g2 = 1 / (1 + ggxLambda(cosI, alpha) + ggxLambda(cosO, alpha));
  return ggxDistribution(cosH, alpha) * g2 / (4 * cosI * cosO);
}

/// f / albedo for light arriving along toLight and leaving towards the viewer;
/// n, toViewer and toLight are unit vectors. Diffuse: 1/pi. Phong:
/// (1 - ks)/pi + ks (s + 2)/(2 pi) max(0, r.w_i)^s with r the view direction
/// mirrored about n. GGX: (1 - ks)/pi + ks ggxSpecular.
inline double brdfShape(const Material& m, const Vec3& n, const Vec3& toViewer,
                        const Vec3& toLight) {
  constexpr double invPi = std::numbers::inv_pi;
  if (m.type == Material::Type::Diffuse) return invPi;
  if (m.type == Material::Type::Ggx) {
    const Vec3 h = (toViewer + toLight).normalized();
    return (1 - m.specular) * invPi +
           m.specular * ggxSpecular(n.dot(toLight), n.dot(toViewer), n.dot(h), m.roughness);
  }
  const Vec3 mirrored = 2 * n.dot(toViewer) * n - toViewer;
  const double c = std::max(0.0, mirrored.dot(toLight));
  const double lobe = c > 0 ? std::pow(c, m.exponent) : 0.0;
  return (1 - m.specular) * invPi + m.specular * (m.exponent + 2) * 0.5 * invPi * lobe;
}

/// brdfShape at one surface point and view, in float over light directions,
/// for the shadow-ray loops.
class LobeShape {
 public:
  LobeShape(const Material& m, const Eigen::Vector3f& n, const Eigen::Vector3f& toViewer)
      : n_(n),
        v_(toViewer),
        mirrored_(2 * n.dot(toViewer) * n - toViewer),
        phong_(m.type == Material::Type::Phong && m.specular > 0),
        ggx_(m.type == Material::Type::Ggx && m.specular > 0),
        ks_(float(m.specular)),
        s_(float(m.exponent)),
        alpha_(float(m.roughness)),
        cosO_(n.dot(toViewer)) {}

  /// Diffuse: the same 1/pi for every direction.
  bool constant() const { return !phong_ && !ggx_; }

  /// f / albedo for light along the unit direction (dx, dy, dz), cosI = n . d.
  float operator()(float dx, float dy, float dz, float cosI) const {
    constexpr float invPi = std::numbers::inv_pi_v<float>;
    if (phong_) {
      const float c = mirrored_.x() * dx + mirrored_.y() * dy + mirrored_.z() * dz;
      return (1 - ks_) * invPi + ks_ * (s_ + 2) * 0.5f * invPi * (c > 0 ? std::pow(c, s_) : 0.0f);
    }
    if (ggx_) {  // microfacet GGX without Fresnel
      const Eigen::Vector3f h = (Eigen::Vector3f(dx, dy, dz) + v_).normalized();
      return (1 - ks_) * invPi + ks_ * ggxSpecular(cosI, cosO_, n_.dot(h), alpha_);
    }
    return invPi;
  }

 private:
  Eigen::Vector3f n_, v_, mirrored_;
  bool phong_, ggx_;
  float ks_, s_, alpha_, cosO_;
};

}  // namespace acpca
