#pragma once
// Anisotropic glossy lobes, written in a surface's tangent frame: directions
// given by their components along the tangent t, the bitangent b = n x t and
// the normal n. With a fixed view the BRDF folds into each pixel's transport
// row, so anisotropy costs nothing at relight time ([Lehtinen03] uses
// [Ashikhmin00]'s lobe with Nu = 40, Nv = 10).
#include <algorithm>
#include <cmath>
#include <numbers>

namespace acpca {

/// A direction's (or the half vector's) components in the frame (t, b, n).
template <typename T>
struct FrameComponents {
  T t, b, n;
};

/// a + b, the same bits for (a, b) and (b, a) whatever products the compiler
/// fuses into the sum: a quarter turn of the frame then swaps the two tangent
/// axes exactly.
template <typename T>
T unorderedSum(T a, T b) {
  return std::min(a, b) + std::max(a, b);
}

/// [Ashikhmin00]'s specular lobe without its Fresnel factor:
///   sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^((nu (h.t)^2 + nv (h.b)^2) / (1 - (n.h)^2))
///   / ((h.k) max(n.k1, n.k2)),
/// with k either direction (h.k is the same for both). 0 unless both
/// directions are above the surface. Symmetric in the two directions.
template <typename T>
T ashikhminShirleyLobe(T cosI, T cosO, const FrameComponents<T>& h, T cosHk, T nu, T nv) {
  if (cosI <= 0 || cosO <= 0 || h.n <= 0 || cosHk <= 0) return 0;
  // (h.t)^2 + (h.b)^2 = 1 - (n.h)^2, written as the sum so that h = n stays finite.
  const T across = unorderedSum(h.t * h.t, h.b * h.b);
  const T exponent =
      across > T(1e-12) ? unorderedSum(nu * h.t * h.t, nv * h.b * h.b) / across : (nu + nv) / 2;
  const T norm = std::sqrt((nu + 1) * (nv + 1)) / (8 * T(std::numbers::pi));
  return norm * std::pow(h.n, exponent) / (cosHk * std::max(cosI, cosO));
}

/// Schlick's Fresnel, as [Ashikhmin00] takes it: rs + (1 - rs)(1 - cos)^5.
template <typename T>
T schlickFresnel(T cosHk, T rs) {
  const T m = 1 - cosHk, m2 = m * m;
  return rs + (1 - rs) * m2 * m2 * m;
}

/// [Ashikhmin00]'s diffuse term over Rd: 28 / (23 pi) (1 - rs)
/// (1 - (1 - n.k1 / 2)^5)(1 - (1 - n.k2 / 2)^5); 0 below the surface.
template <typename T>
T ashikhminShirleyDiffuse(T cosI, T cosO, T rs) {
  if (cosI <= 0 || cosO <= 0) return 0;
  const auto fifth = [](T x) { return x * x * x * x * x; };
  return 28 / (23 * T(std::numbers::pi)) * (1 - rs) * (1 - fifth(1 - cosI / 2)) *
         (1 - fifth(1 - cosO / 2));
}

/// Anisotropic GGX's distribution of microfacet normals [Heitz14]:
///   1 / (pi au av ((h.t / au)^2 + (h.b / av)^2 + (h.n)^2)^2);
/// integrates to 1 against n.h. au = av is the isotropic GGX.
template <typename T>
T anisotropicGgxDistribution(const FrameComponents<T>& h, T au, T av) {
  if (h.n <= 0) return 0;
  const T x = h.t / au, y = h.b / av, d = unorderedSum(x * x, y * y) + h.n * h.n;
  return 1 / (T(std::numbers::pi) * au * av * d * d);
}

/// Smith's Lambda for anisotropic GGX along a direction w [Heitz14]:
/// (sqrt(1 + ((au w.t)^2 + (av w.b)^2) / (w.n)^2) - 1) / 2.
template <typename T>
T anisotropicGgxLambda(const FrameComponents<T>& w, T au, T av) {
  const T x = au * w.t, y = av * w.b;
  return (std::sqrt(1 + unorderedSum(x * x, y * y) / (w.n * w.n)) - 1) / 2;
}

/// Anisotropic GGX's specular term without Fresnel, D G2 / (4 cos_i cos_o),
/// with Smith's height-correlated masking-shadowing G2 = 1 / (1 + Lambda_i
/// + Lambda_o) (as the isotropic ggxSpecular). Symmetric in i and o.
template <typename T>
T anisotropicGgxSpecular(const FrameComponents<T>& i, const FrameComponents<T>& o,
                         const FrameComponents<T>& h, T au, T av) {
  if (i.n <= 0 || o.n <= 0 || h.n <= 0) return 0;
  const T g2 = 1 / (1 + anisotropicGgxLambda(i, au, av) + anisotropicGgxLambda(o, au, av));
  return anisotropicGgxDistribution(h, au, av) * g2 / (4 * i.n * o.n);
}

}  // namespace acpca
