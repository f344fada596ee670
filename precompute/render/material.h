#pragma once
// Materials separate into an RGB albedo times a scalar "shape" (design.md
// section 3), so each occupied pixel has exactly one transport row.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "precompute/transport/cube_lattice.h"

namespace acpca {

struct Material {
  enum class Type { Diffuse, Phong };
  Type type = Type::Diffuse;
  Eigen::Vector3f albedo{0.5f, 0.5f, 0.5f};
  double specular = 0.0;  ///< Phong ks in [0, 1]
  double exponent = 1.0;  ///< Phong s >= 0
};

/// f / albedo for light arriving along toLight and leaving towards the viewer;
/// n, toViewer and toLight are unit vectors. Diffuse: 1/pi. Phong:
/// (1 - ks)/pi + ks (s + 2)/(2 pi) max(0, r.w_i)^s with r the view direction
/// mirrored about n.
inline double brdfShape(const Material& m, const Vec3& n, const Vec3& toViewer,
                        const Vec3& toLight) {
  constexpr double invPi = std::numbers::inv_pi;
  if (m.type == Material::Type::Diffuse) return invPi;
  const Vec3 mirrored = 2 * n.dot(toViewer) * n - toViewer;
  const double c = std::max(0.0, mirrored.dot(toLight));
  const double lobe = c > 0 ? std::pow(c, m.exponent) : 0.0;
  return (1 - m.specular) * invPi + m.specular * (m.exponent + 2) * 0.5 * invPi * lobe;
}

}  // namespace acpca
