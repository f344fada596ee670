#include "lighting/local_light.h"

#include <algorithm>

#include "core/error.h"
#include "core/text.h"

namespace acpca {

namespace {

constexpr const char* kParameter = "light";

}  // namespace

std::string lightGrammarLines(const std::string& indent) {
  std::string lines;
  for (const LightGrammar& g : kLightGrammars)
    lines += concat(indent, g.grammar, ": ", g.meaning, "\n");
  return lines;
}

std::string LocalLight::canonicalSpec() const {
  std::vector<double> numbers(position.data(), position.data() + 3);
  std::visit([&](const auto& kind) { kind.appendNumbers(numbers); }, shape);
  if (emission.x() == emission.y() && emission.y() == emission.z())
    numbers.push_back(emission.x());
  else
    numbers.insert(numbers.end(), emission.data(), emission.data() + 3);
  std::string text = concat(kindName(), ":");
  for (size_t i = 0; i < numbers.size(); ++i) {
    if (i > 0) text += ',';  // piece by piece: GCC 12 warns of "," + string (-Wrestrict)
    text += shortestNumberText(numbers[i]);
  }
  return text;
}

void validateLocalLight(LocalLight& light) {
  if (light.spec.empty()) light.spec = light.canonicalSpec();
  const auto refuse = [&](const std::string& problem) {
    throw ParameterError(kParameter, light.spec, problem);
  };
  // Bounds that keep every square and product of the relight finite in float.
  if (!light.position.allFinite() || light.position.cwiseAbs().maxCoeff() > kMaxLightCoordinate)
    refuse(concat("its position must be finite, within +-", kMaxLightCoordinate));
  const char* emission = std::visit([](const auto& kind) { return kind.kEmission; }, light.shape);
  if (!light.emission.allFinite() || light.emission.minCoeff() < 0 ||
      light.emission.maxCoeff() > kMaxLightEmission)
    refuse(concat("its ", emission, " must be finite and in [0, ", kMaxLightEmission, "]"));
  const std::string problem = std::visit([](auto& kind) { return kind.problem(); }, light.shape);
  if (!problem.empty()) refuse(problem);
}

std::optional<LocalLight> heldAsPoint(const LocalLight& light) {
  const std::optional<double> scale =
      std::visit([](const auto& kind) { return kind.heldPointScale(); }, light.shape);
  if (!scale) return std::nullopt;
  LocalLight point = light;
  point.emission *= *scale;
  point.shape = PointLight{};
  point.spec = point.canonicalSpec();
  return point;
}

double lightIrradiance(const LocalLight& light, const Vec3& point) {
  const Vec3 toLight = light.position - point;
  return std::visit([&](const auto& kind) { return kind.irradiance(toLight); }, light.shape);
}

bool appendDirectionTaps(const LocalLight& light, const CubeLattice& lattice, const Vec3& point,
                         std::vector<LightTap>& taps) {
  const Vec3 toLight = light.position - point;
  return std::visit(
      [&](const auto& kind) {
        // The kind's irradiance is negative where the point is inside or on it.
        if (!(kind.irradiance(toLight) >= 0)) return false;
        kind.appendDirectionShares(lattice, toLight, taps);
        return true;
      },
      light.shape);
}

bool appendLightTaps(const LocalLight& light, const CubeLattice& lattice, const Vec3& point,
                     std::vector<LightTap>& taps) {
  const double irradiance = lightIrradiance(light, point);
  if (irradiance < 0) return false;
  if (irradiance == 0) return true;
  const size_t start = taps.size();
  appendDirectionTaps(light, lattice, point, taps);
  for (size_t i = start; i < taps.size(); ++i) taps[i].weight *= irradiance;
  return true;
}

LatticeLighting localLighting(const std::vector<LocalLight>& lights, const CubeLattice& lattice,
                              const Vec3& point) {
  LatticeLighting lighting(3 * static_cast<size_t>(lattice.size()), 0.0);
  std::vector<LightTap> taps;
  for (const LocalLight& light : lights) {
    taps.clear();
    if (!appendLightTaps(light, lattice, point, taps))
      throw ParameterError(kParameter, light.spec, "encloses or touches the point it is seen from");
    for (const LightTap& tap : taps)
      for (int c = 0; c < 3; ++c) lighting[3 * tap.texel + c] += tap.weight * light.emission[c];
  }
  return lighting;
}

}  // namespace acpca
