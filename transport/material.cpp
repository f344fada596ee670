#include "transport/material.h"

#include "core/error.h"

namespace acpca {

namespace {

/// Ten turns either way: enough for any scene, and far from where a turn
/// count stops being exact.
constexpr double kMaxRotationDegrees = 3600;

/// "field: value is outside [lo, hi]" unless lo <= value <= hi.
std::string outside(const char* field, double value, double lo, double hi) {
  if (value >= lo && value <= hi) return {};
  return concat(field, " ", value, " is outside [", lo, ", ", hi, "]");
}

}  // namespace

std::string materialProblem(const Material& m) {
  using Type = Material::Type;
  if (m.type == Type::Diffuse) return {};
  if (auto p = outside("specular", m.specular, 0, 1); !p.empty()) return p;
  if (m.type == Type::Phong) return outside("exponent", m.exponent, 0, 1e6);
  if (m.type == Type::Ggx) {
    if (auto p = outside("roughness", m.roughness, kMinRoughness, kMaxRoughness); !p.empty())
      return p;
    if (m.roughnessV != 0)
      if (auto p = outside("roughness_v", m.roughnessV, kMinRoughness, kMaxRoughness); !p.empty())
        return p;
  }
  if (m.type == Type::AshikhminShirley) {
    // The lobe's exponents: 0 or below has no peak (and no normalisation).
    if (!(m.nu > 0 && m.nu <= 1e6)) return concat("nu ", m.nu, " is outside (0, 1e6]");
    if (!(m.nv > 0 && m.nv <= 1e6)) return concat("nv ", m.nv, " is outside (0, 1e6]");
  }
  if (auto p = outside("rotation", m.rotationDegrees, -kMaxRotationDegrees, kMaxRotationDegrees);
      !p.empty())
    return p;
  return {};
}

std::string describeMaterial(const Material& m) {
  using Type = Material::Type;
  std::string text{kMaterialTypeNames.name(m.type)};
  if (m.type == Type::Phong) return concat(text, " ks ", m.specular, " exponent ", m.exponent);
  if (m.type == Type::Ggx) {
    text = concat(text, " ks ", m.specular, " roughness ", m.alphaU());
    if (m.anisotropic()) text = concat(text, " x ", m.alphaV());
  }
  if (m.type == Type::AshikhminShirley)
    text = concat(text, " rs ", m.specular, " nu ", m.nu, " nv ", m.nv);
  if (m.rotationDegrees != 0) text = concat(text, " rotation ", m.rotationDegrees);
  return text;
}

}  // namespace acpca
