#pragma once
// Materials separate into an RGB albedo times a scalar "shape" (docs/design.md
// section 3), so each occupied pixel has exactly one transport row.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/enum_names.h"
#include "transport/anisotropic_lobes.h"
#include "transport/cube_lattice.h"

namespace acpca {

/// Below this GGX is a mirror no lattice resolves.
inline constexpr double kMinRoughness = 1e-3;
/// The roughest GGX axis: 1 / sqrt(0.1), roughness 1 at anisotropy 1 (Cycles').
inline constexpr double kMaxRoughness = 3.1622776601683795;

struct Material {
  enum class Type { Diffuse, Phong, Ggx, AshikhminShirley };
  Type type = Type::Diffuse;
  Eigen::Vector3f albedo{0.5f, 0.5f, 0.5f};
  /// ks in [0, 1]: Phong's and GGX's specular share of the albedo;
  /// Ashikhmin-Shirley's Rs, the specular reflectance at normal incidence.
  double specular = 0.0;
  double exponent = 1.0;  ///< Phong s >= 0
  /// GGX alpha along the tangent, in [kMinRoughness, kMaxRoughness]; along
  /// the bitangent too unless roughnessV is set.
  double roughness = 0.5;
  double roughnessV = 0;       ///< GGX alpha along the bitangent; 0: roughness (isotropic)
  double nu = 1, nv = 1;       ///< Ashikhmin-Shirley exponents along tangent and bitangent, > 0
  double rotationDegrees = 0;  ///< the tangent turned about the normal (counter-clockwise)

  double alphaU() const { return roughness; }
  double alphaV() const { return roughnessV > 0 ? roughnessV : roughness; }
  /// Whether the lobe depends on the tangent's direction.
  bool anisotropic() const {
    return (type == Type::Ggx && alphaV() != alphaU()) ||
           (type == Type::AshikhminShirley && nu != nv);
  }
};
/// A material's "type" in scene JSON.
inline constexpr EnumNames<Material::Type, 4> kMaterialTypeNames{
    "material type",
    {{{Material::Type::Diffuse, "diffuse"},
      {Material::Type::Phong, "phong"},
      {Material::Type::Ggx, "ggx"},
      {Material::Type::AshikhminShirley, "ashikhmin-shirley"}}}};

/// What is wrong with a material's parameters, naming the field and the
/// allowed range (JSON's names: "specular", "roughness_v", "nu"...); empty
/// when nothing is. The albedo is checked by whoever holds one.
std::string materialProblem(const Material& m);
/// A material's kind and parameters in one line, as `info` prints them
/// ("ggx ks 0.5 roughness 0.2 x 0.05 rotation 30").
std::string describeMaterial(const Material& m);

/// Rec. 709 luminance of a linear RGB value: weighs albedos inside a pixel.
inline float luminance(const Eigen::Vector3f& rgb) {
  return 0.2126f * rgb.x() + 0.7152f * rgb.y() + 0.0722f * rgb.z();
}

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

/// The tangent t' of a surface point: t (unit, across the normal n) turned
/// by `degrees` about n, cos t + sin (n x t); exact at multiples of 90
/// degrees, so that a quarter turn swaps the two axes exactly.
template <typename V>
V turnedTangent(const V& n, const V& t, double degrees) {
  const double turns = degrees / 90;
  if (turns == std::round(turns)) {
    const V b = n.cross(t);
    switch (((static_cast<long long>(turns) % 4) + 4) % 4) {
      case 0:
        return t;
      case 1:
        return b;
      case 2:
        return -t;
      default:
        return -b;
    }
  }
  const double a = degrees * std::numbers::pi / 180;
  using S = typename V::Scalar;
  return (S(std::cos(a)) * t + S(std::sin(a)) * n.cross(t)).normalized();
}

/// A unit tangent across the unit normal n from a direction `along` (any
/// length): along's part across n, or, where along is (nearly) parallel to
/// n, world +X's part across n (+Z's where n is along X).
template <typename V>
V tangentAcross(const V& n, const V& along) {
  using S = typename V::Scalar;
  V t = along - n.dot(along) * n;
  if (t.squaredNorm() > S(1e-12) * std::max(S(1), along.squaredNorm())) return t.normalized();
  const V x = std::abs(n.x()) < S(0.9) ? V::UnitX() : V::UnitZ();
  return (x - n.dot(x) * n).normalized();
}

/// The anisotropic lobes of a material over albedo, f / albedo, given the
/// light's, the viewer's and the half vector's components in the shading
/// frame (t, n x t, n). Ashikhmin-Shirley, a stated variant of
/// [Ashikhmin00] in the albedo-times-shape form (docs/design.md): its
/// diffuse term with Rd the albedo, plus the lobe times Schlick's Fresnel
/// of Rs = ks, tinted by the albedo. GGX: (1 - ks)/pi + ks D G2/(4 cos_i cos_o).
template <typename T>
T frameLobeShape(const Material& m, const FrameComponents<T>& i, const FrameComponents<T>& o,
                 const FrameComponents<T>& h, T cosHk) {
  const T ks = T(m.specular);
  if (m.type == Material::Type::AshikhminShirley) {
    const T lobe = ashikhminShirleyLobe(i.n, o.n, h, cosHk, T(m.nu), T(m.nv));
    return ashikhminShirleyDiffuse(i.n, o.n, ks) + lobe * schlickFresnel(cosHk, ks);
  }
  return (1 - ks) * std::numbers::inv_pi_v<T> +
         ks * anisotropicGgxSpecular(i, o, h, T(m.alphaU()), T(m.alphaV()));
}

/// f / albedo for light arriving along toLight and leaving towards the viewer;
/// n, tangent (across n, with the material's rotation applied), toViewer and
/// toLight are unit vectors. Diffuse: 1/pi. Phong: (1 - ks)/pi + ks (s + 2)/
/// (2 pi) max(0, r.w_i)^s with r the view direction mirrored about n. GGX:
/// (1 - ks)/pi + ks ggxSpecular. Ashikhmin-Shirley and anisotropic GGX:
/// frameLobeShape.
inline double brdfShape(const Material& m, const Vec3& n, const Vec3& tangent, const Vec3& toViewer,
                        const Vec3& toLight) {
  constexpr double invPi = std::numbers::inv_pi;
  if (m.type == Material::Type::Diffuse) return invPi;
  if (m.type == Material::Type::Ggx && !m.anisotropic()) {
    const Vec3 h = (toViewer + toLight).normalized();
    return (1 - m.specular) * invPi +
           m.specular * ggxSpecular(n.dot(toLight), n.dot(toViewer), n.dot(h), m.roughness);
  }
  if (m.type == Material::Type::Phong) {
    const Vec3 mirrored = 2 * n.dot(toViewer) * n - toViewer;
    const double c = std::max(0.0, mirrored.dot(toLight));
    const double lobe = c > 0 ? std::pow(c, m.exponent) : 0.0;
    return (1 - m.specular) * invPi + m.specular * (m.exponent + 2) * 0.5 * invPi * lobe;
  }
  const Vec3 b = n.cross(tangent), h = (toViewer + toLight).normalized();
  const auto in = [&](const Vec3& d) {
    return FrameComponents<double>{tangent.dot(d), b.dot(d), n.dot(d)};
  };
  return frameLobeShape(m, in(toLight), in(toViewer), in(h), h.dot(toLight));
}

/// brdfShape at one surface point and view, in float over light directions,
/// for the shadow-ray loops.
class LobeShape {
 public:
  LobeShape(const Material& m, const Eigen::Vector3f& n, const Eigen::Vector3f& tangent,
            const Eigen::Vector3f& toViewer)
      : material_(m),
        n_(n),
        t_(tangent),
        b_(n.cross(tangent)),
        v_(toViewer),
        mirrored_(2 * n.dot(toViewer) * n - toViewer),
        phong_(m.type == Material::Type::Phong && m.specular > 0),
        ggx_(m.type == Material::Type::Ggx && m.specular > 0 && !m.anisotropic()),
        frame_(m.type == Material::Type::AshikhminShirley ||
               (m.type == Material::Type::Ggx && m.anisotropic())),
        ks_(float(m.specular)),
        s_(float(m.exponent)),
        alpha_(float(m.roughness)),
        cosO_(n.dot(toViewer)),
        o_{t_.dot(toViewer), b_.dot(toViewer), cosO_} {}

  /// Diffuse: the same 1/pi for every direction.
  bool constant() const { return !phong_ && !ggx_ && !frame_; }

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
    if (frame_) {
      const Eigen::Vector3f d(dx, dy, dz), h = (d + v_).normalized();
      return frameLobeShape<float>(material_, {t_.dot(d), b_.dot(d), cosI}, o_,
                                   {t_.dot(h), b_.dot(h), n_.dot(h)}, h.dot(d));
    }
    return invPi;
  }

 private:
  Material material_;
  Eigen::Vector3f n_, t_, b_, v_, mirrored_;
  bool phong_, ggx_, frame_;
  float ks_, s_, alpha_, cosO_;
  FrameComponents<float> o_;
};

}  // namespace acpca
