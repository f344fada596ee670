#include "precompute/sampling_advice.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace acpca {

namespace {

double phongHalfWidth(double exponent) {
  return std::acos(std::pow(0.5, 1 / exponent));
}

int texelRaysForHalfWidth(double halfWidth, int cubemapResolution) {
  if (halfWidth <= 0) return 1;
  // Two samples across the lobe's half width: on a Phong sphere under constant
  // light (s = 1000, 5000) its integral is then within 4% on average, 20% at worst.
  const double rays = std::pow(2 * (2.0 / cubemapResolution) / halfWidth, 2);
  return static_cast<int>(std::clamp(std::ceil(rays), 1.0, 1024.0));
}

}  // namespace

double lobeHalfWidth(const Material& m) {
  if (m.specular <= 0) return 0;
  if (m.type == Material::Type::Phong) return m.exponent > 0 ? phongHalfWidth(m.exponent) : 0;
  if (m.type == Material::Type::AshikhminShirley)  // in half vectors: twice as wide in light
    return 2 * phongHalfWidth(std::max(m.nu, m.nv));
  if (m.type == Material::Type::Ggx) {
    // D falls to half its peak where cos^2 theta_h = (1 - sqrt2 a^2) / (1 - a^2);
    // mirrored about the normal, the lobe of light directions is twice as wide.
    // Anisotropic: across its narrower axis.
    const double a = std::min(m.alphaU(), m.alphaV()), a2 = a * a;
    if (std::sqrt(2.0) * a2 >= 1) return 0;  // wider than any lattice misses
    return 2 * std::acos(std::sqrt((1 - std::sqrt(2.0) * a2) / (1 - a2)));
  }
  return 0;
}

int texelRaysForLobe(double exponent, int cubemapResolution) {
  return exponent <= 0 ? 1 : texelRaysForHalfWidth(phongHalfWidth(exponent), cubemapResolution);
}

std::vector<std::string> samplingWarnings(const Scene& scene, const PrecomputeOptions& options) {
  std::vector<std::string> warnings;
  const double spacing = 2.0 / options.cubemapResolution / std::sqrt(double(options.texelRays));
  const auto check = [&](const Material& m, const std::string& object) {
    const double halfWidth = lobeHalfWidth(m);
    if (halfWidth <= 0 || spacing <= halfWidth) return;  // two samples across the half maximum
    const std::string lobe = m.type == Material::Type::Phong ? concat("Phong exponent ", m.exponent)
                             : m.type == Material::Type::Ggx
                                 ? concat("GGX roughness ", std::min(m.alphaU(), m.alphaV()))
                                 : concat("Ashikhmin-Shirley exponent ", std::max(m.nu, m.nv));
    warnings.push_back(concat(object, ": ", lobe, " has a lobe ", 2 * halfWidth * 180 / M_PI,
                              " degrees wide at half maximum, under two direction samples across (",
                              spacing * 180 / M_PI, " degrees apart on 6x",
                              options.cubemapResolution, "x", options.cubemapResolution, " with ",
                              options.texelRays, " ray(s) per texel): its highlights alias; ",
                              texelRaysForHalfWidth(halfWidth, options.cubemapResolution),
                              " rays per texel or a larger cube map resolve it"));
  };
  for (const auto& mesh : scene.meshes) check(mesh.material, concat("mesh '", mesh.name, "'"));
  for (size_t i = 0; i < scene.spheres.size(); ++i)
    check(scene.spheres[i].material, concat("sphere ", i));
  return warnings;
}

}  // namespace acpca
