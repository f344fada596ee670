#include "lighting/environment.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string_view>

#include "core/error.h"
#include "lighting/spec_parsing.h"

namespace acpca {

void Environment::integrateMany(const CubeLattice& lattice,
                                const std::vector<Eigen::Matrix3d>& rotations,
                                const std::vector<LatticeLighting*>& lightings) const {
  ACPCA_CHECK(rotations.size() == lightings.size(), rotations.size(), " rotations, ",
              lightings.size(), " lightings");
  // Each rotation on a task of its own: one integration keeps only a few
  // cores busy.
  tbb::parallel_for(size_t(0), rotations.size(),
                    [&](size_t k) { integrate(lattice, rotations[k], *lightings[k]); });
}

void integrateSmoothFunction(const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                             const std::function<Rgb(const Vec3&)>& radiance, int sub,
                             LatticeLighting& lighting) {
  ACPCA_CHECK(lighting.size() == 3u * lattice.size(), "lighting size ", lighting.size());
  const double step = 2.0 / lattice.resolution(), cell = step / sub;
  const Eigen::Matrix3d inverse = rotation.transpose();
  // Each texel writes only its own entries: parallel and deterministic.
  tbb::parallel_for(0, lattice.size(), [&](int j) {
    const TexelCoord c = lattice.texelCoord(j);
    Rgb sum = Rgb::Zero();
    for (int a = 0; a < sub; ++a)
      for (int b = 0; b < sub; ++b) {
        const double s0 = -1 + c.col * step + b * cell, t0 = -1 + c.row * step + a * cell;
        const double omega = CubeLattice::rectangleSolidAngle(s0, t0, s0 + cell, t0 + cell);
        const Vec3 w =
            CubeLattice::faceDirection(c.face, s0 + 0.5 * cell, t0 + 0.5 * cell).normalized();
        sum += omega * radiance(inverse * w);
      }
    for (int ch = 0; ch < 3; ++ch) lighting[3 * j + ch] += sum[ch];
  });
}

namespace {

std::vector<double> parseNumbers(const std::string& list, const std::string& spec) {
  std::vector<double> values;
  std::stringstream in(list);
  std::string part;
  while (std::getline(in, part, ','))
    values.push_back(parseFiniteNumber(part, "environment", spec));
  return values;
}

}  // namespace

std::string environmentGrammarList() {
  std::string list;
  for (const EnvironmentGrammar& g : kEnvironmentGrammars)
    list += concat(list.empty() ? "" : ", ", g.grammar);
  return list;
}

bool isAnalyticEnvironment(const std::string& spec) {
  return std::any_of(kEnvironmentGrammars.begin(), kEnvironmentGrammars.end(),
                     [&](const EnvironmentGrammar& g) {
                       const std::string_view prefix = g.prefix;
                       return prefix.back() == ':' ? spec.rfind(prefix, 0) == 0 : spec == prefix;
                     });
}

std::unique_ptr<Environment> loadEnvironment(const std::string& spec) {
  ++specParseCounts().lightings;
  const auto& [constant, sun, sky] = kEnvironmentGrammars;
  if (spec == sky.prefix) return makeSkyEnvironment();
  if (spec.rfind(constant.prefix, 0) == 0) {
    const auto v = parseNumbers(spec.substr(std::string_view(constant.prefix).size()), spec);
    if (v.size() != 1 && v.size() != 3)
      throw ParameterError("environment", spec, concat("expected ", constant.grammar));
    const Rgb radiance = v.size() == 1 ? Rgb::Constant(v[0]) : Rgb(v[0], v[1], v[2]);
    if ((radiance.array() < 0).any())
      throw ParameterError("environment", spec, "radiance must be >= 0");
    return makeConstantEnvironment(radiance);
  }
  if (spec.rfind(sun.prefix, 0) == 0) {
    const auto v = parseNumbers(spec.substr(std::string_view(sun.prefix).size()), spec);
    if (v.size() != 4) throw ParameterError("environment", spec, concat("expected ", sun.grammar));
    if (!(v[2] > 0 && v[2] <= 180))
      throw ParameterError("environment", spec, "SIZE_DEG must be in (0, 180]");
    if (v[3] < 0) throw ParameterError("environment", spec, "INTENSITY must be >= 0");
    return makeSunEnvironment(v[0], v[1], v[2], Rgb::Constant(v[3]));
  }
  if (!std::filesystem::exists(spec))
    throw ParameterError("environment", spec,
                         concat("no such file, and not ", environmentGrammarList()));
  return loadEnvironmentImage(spec);
}

namespace {
bool isImageFile(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return std::ranges::find(kMapFileExtensions, ext) != kMapFileExtensions.end();
}
}  // namespace

std::vector<std::string> expandEnvironmentSpecs(const std::vector<std::string>& specs) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const auto& spec : specs) {
    if (!isAnalyticEnvironment(spec) && fs::is_directory(spec)) {
      std::vector<std::string> files;
      for (const auto& entry : fs::directory_iterator(spec))
        if (entry.is_regular_file() && isImageFile(entry.path()))
          files.push_back(entry.path().string());
      if (files.empty())
        throw ParameterError("environment", spec, "the directory holds no .exr/.hdr maps");
      std::sort(files.begin(), files.end());
      out.insert(out.end(), files.begin(), files.end());
    } else {
      out.push_back(spec);
    }
  }
  return out;
}

}  // namespace acpca
