// Light specs: a light parsed from its text, a sweep of them expanded and a
// light path read (docs/lighting.md, "Local lights").
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/text.h"
#include "lighting/local_light.h"
#include "lighting/spec_parsing.h"

namespace acpca {

namespace {

constexpr const char* kParameter = "light";

std::vector<std::string> splitNumbers(const std::string& text, char separator = ',') {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(separator, start);
    parts.push_back(text.substr(start, comma == std::string::npos ? comma : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return parts;
}

/// The kind a spec names before its colon; a ParameterError naming the spec
/// and listing the kinds otherwise.
size_t lightKindOf(const std::string& spec, size_t colon) {
  const std::string name = spec.substr(0, colon);
  if (const std::optional<size_t> kind = lightKindNamed(name)) return *kind;
  throw ParameterError(kParameter, spec, concat("'", name, "' is not one of ", lightKindList()));
}

}  // namespace

bool isLightSweep(const std::string& spec) {
  const size_t colon = spec.find(':');
  return colon != std::string::npos && spec.find(':', colon + 1) != std::string::npos;
}

std::vector<std::string> expandLightSweep(const std::string& spec) {
  ++specParseCounts().lightSweeps;
  if (!isLightSweep(spec)) return {spec};
  const size_t colon = spec.find(':');
  // The kind and every number checked before anything is expanded, and the
  // numbers written short: a sweep's copies stay small (fuzzing grew one of
  // 65,536 copies of 600 bytes of junk past 2 GiB).
  lightKindOf(spec, colon);
  const std::vector<std::string> parts = splitNumbers(spec.substr(colon + 1));
  if (parts.size() > kMaxLightNumbers)
    throw ParameterError(
        kParameter, spec,
        concat("has ", parts.size(), " numbers; a light has at most ", kMaxLightNumbers));
  // Per number its values: one, or a sweep's.
  std::vector<std::vector<std::string>> values;
  long long combinations = 1;
  for (const std::string& part : parts) {
    if (part.find(':') == std::string::npos) {
      values.push_back({shortestNumberText(parseFiniteNumber(part, kParameter, spec))});
      continue;
    }
    const std::vector<std::string> sweep = splitNumbers(part, ':');
    if (sweep.size() != 3)
      throw ParameterError(kParameter, spec, concat("'", part, "' is not a sweep A:B:S"));
    const double a = parseFiniteNumber(sweep[0], kParameter, spec),
                 b = parseFiniteNumber(sweep[1], kParameter, spec),
                 step = parseFiniteNumber(sweep[2], kParameter, spec);
    if (!(step > 0))
      throw ParameterError(kParameter, spec, concat("'", part, "': the step must be > 0"));
    if (!(b > a))
      throw ParameterError(kParameter, spec, concat("'", part, "': the end must exceed the start"));
    // At least A itself: a step wider than B - A (fuzzing found 2e73) would
    // otherwise round the count to zero and the sweep to no light at all.
    const double count = std::max(1.0, std::ceil((b - a) / step - 1e-9));
    combinations *= static_cast<long long>(std::min(count, 1e12));
    if (count > kMaxLightSweepSpecs || combinations > kMaxLightSweepSpecs)
      throw ParameterError(kParameter, spec,
                           concat("sweeps more than ", kMaxLightSweepSpecs, " lights"));
    values.emplace_back();
    for (long long i = 0; i < static_cast<long long>(count); ++i)
      values.back().push_back(shortestNumberText(a + i * step));
  }
  std::vector<std::string> specs{spec.substr(0, colon + 1)};
  for (size_t n = 0; n < values.size(); ++n) {
    std::vector<std::string> longer;
    for (const std::string& head : specs)
      for (const std::string& v : values[n]) longer.push_back(head + (n == 0 ? "" : ",") + v);
    specs = std::move(longer);
  }
  return specs;
}

LocalLight parseLocalLight(const std::string& spec) {
  ++specParseCounts().lights;
  const size_t colon = spec.find(':');
  if (colon == std::string::npos)
    throw ParameterError(kParameter, spec,
                         concat("is not KIND:NUMBERS with KIND one of ", lightKindList(),
                                " (docs/lighting.md, \"Local lights\")"));
  const size_t kind = lightKindOf(spec, colon);
  std::vector<double> v;
  for (const std::string& part : splitNumbers(spec.substr(colon + 1)))
    v.push_back(parseFiniteNumber(part, kParameter, spec));
  const LightGrammar& g = kLightGrammars[kind];
  const size_t before = g.numbersBeforeEmission;
  if (v.size() != before + 1 && v.size() != before + 3)
    throw ParameterError(kParameter, spec, concat("has ", v.size(), " numbers; write ", g.grammar));
  LocalLight light;
  light.position = Vec3(v[0], v[1], v[2]);
  light.shape = lightShapeFrom(kind, v.data() + 3);
  light.emission = v.size() == before + 1 ? Rgb::Constant(v[before])
                                          : Rgb(v[before], v[before + 1], v[before + 2]);
  light.spec = spec;
  validateLocalLight(light);
  return light;
}

std::vector<std::vector<LocalLight>> readLightPath(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UserError(concat(path, ": cannot read the light path"));
  std::vector<std::vector<LocalLight>> frames;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::replace(line.begin(), line.end(), ';', ' ');
    std::istringstream words(line);
    std::vector<LocalLight> lights;
    for (std::string spec; words >> spec;) {
      if (lights.empty() && spec[0] == '#') break;
      try {
        lights.push_back(parseLocalLight(spec));
      } catch (const ParameterError& e) {
        throw UserError(concat(path, ":", number, ": light '", spec, "': ", e.problem()));
      }
    }
    if (!lights.empty()) frames.push_back(std::move(lights));
  }
  if (in.bad()) throw UserError(concat(path, ": cannot read the light path"));
  if (frames.empty()) throw UserError(concat(path, ": the light path holds no lights"));
  return frames;
}

}  // namespace acpca
