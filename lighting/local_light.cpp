#include "lighting/local_light.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.h"
#include "lighting/spec_parsing.h"

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr const char* kParameter = "light";

/// The shortest text that reads back as the same double: a light's spec
/// in a manifest or from Python gives the very light again.
std::string formatNumber(double v) {
  std::array<char, 32> text;
  const auto end = std::to_chars(text.data(), text.data() + text.size(), v).ptr;
  return std::string(text.data(), end);
}

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

/// Grey (one value) or RGB (three) emission from the numbers at `first`.
Rgb emissionFrom(const std::vector<double>& v, size_t first) {
  return v.size() == first + 1 ? Rgb::Constant(v[first])
                               : Rgb(v[first], v[first + 1], v[first + 2]);
}

/// Spot falloff: 1 inside the inner cone, 0 outside the half angle, a
/// smoothstep in the cosine over the outer kSpotFalloffShare between.
double spotFalloff(const SpotLight& light, const Vec3& fromLight) {
  const double half = light.halfAngleDegrees * kPi / 180;
  const double cosOuter = std::cos(half), cosInner = std::cos((1 - kSpotFalloffShare) * half);
  const double t =
      std::clamp((light.axis.dot(fromLight) - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

/// The four great circles bounding a texel, as inward unit normals: a
/// direction w lies in the texel when every n . w >= 0, and a cap of angular
/// radius alpha around w lies in it when every n . w >= sin(alpha).
std::array<Vec3, 4> texelBoundaryNormals(const CubeLattice& lattice, int texel) {
  const TexelCoord t = lattice.texelCoord(texel);
  const double step = 2.0 / lattice.resolution();
  const double s0 = -1 + t.col * step, s1 = s0 + step, t0 = -1 + t.row * step, t1 = t0 + step;
  const Vec3 centre = lattice.direction(texel);
  const auto plane = [&](const Vec3& a, const Vec3& b) {
    Vec3 n = a.cross(b).normalized();
    return n.dot(centre) >= 0 ? n : Vec3(-n);
  };
  const auto at = [&](double s, double tt) { return CubeLattice::faceDirection(t.face, s, tt); };
  return {plane(at(s0, t0), at(s0, t1)), plane(at(s1, t0), at(s1, t1)),
          plane(at(s0, t0), at(s1, t0)), plane(at(s0, t1), at(s1, t1))};
}

/// Per face, the box (s min, s max, t min, t max) of face coordinates a cap
/// covers there: its rim's points, its centre and the face corners inside it
/// (a face it misses has s min > s max).
using FaceBoxes = std::array<std::array<double, 4>, 6>;
FaceBoxes capFaceBoxes(const Vec3& axis, double cosAlpha, double sinAlpha, int rimPoints) {
  FaceBoxes box;
  for (auto& b : box) b = {2, -2, 2, -2};
  const auto addPoint = [&](int face, double s, double t) {
    auto& b = box[face];
    b = {std::min(b[0], s), std::max(b[1], s), std::min(b[2], t), std::max(b[3], t)};
  };
  const auto add = [&](const Vec3& d) {
    int face;
    double s, t;
    CubeLattice::faceCoordinates(d, face, s, t);
    addPoint(face, s, t);
  };
  add(axis);
  const Vec3 helper = std::abs(axis.y()) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 u = axis.cross(helper).normalized(), v = axis.cross(u);
  for (int i = 0; i < rimPoints; ++i) {
    const double phi = 2 * kPi * i / rimPoints;
    add(cosAlpha * axis + sinAlpha * (std::cos(phi) * u + std::sin(phi) * v));
  }
  for (int face = 0; face < 6; ++face)
    for (double s : {-1.0, 1.0})
      for (double t : {-1.0, 1.0})
        if (CubeLattice::faceDirection(face, s, t).normalized().dot(axis) >= cosAlpha)
          addPoint(face, s, t);
  // Where the rim leaves a face between two of its points the cap runs on to
  // the edge: widen by a rim step (an angle, stretched at most 3x on a face).
  const double margin = 3 * 2 * kPi * sinAlpha / rimPoints;
  for (auto& b : box)
    if (b[0] <= b[1]) b = {b[0] - margin, b[1] + margin, b[2] - margin, b[3] + margin};
  return box;
}

/// Cells of a face's texel grid `perSide` to a side covering `box`, one cell wider.
template <typename Visit>
void cellsOver(const std::array<double, 4>& box, int perSide, Visit&& visit) {
  const double step = 2.0 / perSide;
  const auto cell = [&](double c) {
    return std::clamp(static_cast<int>(std::floor((c + 1) / step)), 0, perSide - 1);
  };
  for (int row = std::max(0, cell(box[2]) - 1); row <= std::min(perSide - 1, cell(box[3]) + 1);
       ++row)
    for (int col = std::max(0, cell(box[0]) - 1); col <= std::min(perSide - 1, cell(box[1]) + 1);
         ++col)
      visit(row, col, -1 + col * step, -1 + row * step, step);
}

/// A cap up to a couple of texels across on a grid of cells about alpha / 12
/// wide that divides every texel (so texel edges are cell edges): each cell
/// whose centre is inside adds its solid angle, area / (1 + s^2 + t^2)^(3/2),
/// to its texel.
void capByCells(const CubeLattice& lattice, const Vec3& axis, double cosAlpha, double sinAlpha,
                double alpha, double texelAngle, std::vector<LightTap>& taps) {
  const int res = lattice.resolution();
  const int perTexel = std::clamp(static_cast<int>(std::ceil(12 * texelAngle / alpha)), 3, 64);
  const FaceBoxes box = capFaceBoxes(axis, cosAlpha, sinAlpha, 128);
  const double cos2 = cosAlpha * cosAlpha;
  const size_t start = taps.size();
  for (int face = 0; face < 6; ++face) {
    if (box[face][0] > box[face][1]) continue;
    cellsOver(box[face], res * perTexel, [&](int row, int col, double s0, double t0, double step) {
      const double s = s0 + 0.5 * step, t = t0 + 0.5 * step, r2 = 1 + s * s + t * t;
      const double along = CubeLattice::faceDirection(face, s, t).dot(axis);
      if (along <= 0 || along * along < cos2 * r2) return;
      const int texel = lattice.texelIndex({face, row / perTexel, col / perTexel});
      const double solidAngle = step * step / (r2 * std::sqrt(r2));
      auto tap = std::find_if(taps.begin() + start, taps.end(),
                              [&](const LightTap& x) { return x.texel == texel; });
      if (tap == taps.end())
        taps.push_back({texel, solidAngle});
      else
        tap->weight += solidAngle;
    });
  }
}

/// A large cap texel by texel: texels whose corners are all inside take their
/// exact solid angle, texels on its rim the solid angle of the 8x8 sub-cells
/// whose centres are inside.
void capByTexels(const CubeLattice& lattice, const Vec3& axis, double cosAlpha, double sinAlpha,
                 std::vector<LightTap>& taps) {
  const auto inside = [&](const Vec3& d) { return d.normalized().dot(axis) >= cosAlpha; };
  const FaceBoxes box = capFaceBoxes(axis, cosAlpha, sinAlpha, 256);
  constexpr int kSub = 8;
  for (int face = 0; face < 6; ++face) {
    if (box[face][0] > box[face][1]) continue;
    cellsOver(box[face], lattice.resolution(),
              [&](int row, int col, double s0, double t0, double step) {
                const int texel = lattice.texelIndex({face, row, col});
                int cornersInside = 0;
                for (int corner = 0; corner < 4; ++corner)
                  cornersInside += inside(CubeLattice::faceDirection(face, s0 + (corner & 1) * step,
                                                                     t0 + (corner >> 1) * step));
                if (cornersInside == 4) {  // a cap under 90 degrees is convex: all inside
                  taps.push_back({texel, lattice.solidAngle(texel)});
                  return;
                }
                double covered = 0;
                const double sub = step / kSub;
                for (int a = 0; a < kSub; ++a)
                  for (int c = 0; c < kSub; ++c) {
                    const double s = s0 + (c + 0.5) * sub, t = t0 + (a + 0.5) * sub;
                    if (!inside(CubeLattice::faceDirection(face, s, t))) continue;
                    covered += CubeLattice::rectangleSolidAngle(s - 0.5 * sub, t - 0.5 * sub,
                                                                s + 0.5 * sub, t + 0.5 * sub);
                  }
                if (covered > 0) taps.push_back({texel, covered});
              });
  }
}

/// A sphere's solid angle seen from a point at distance d from its centre,
/// 2 pi (1 - cos alpha) with sin alpha = radius / d, without cancellation.
double sphereSolidAngle(double radius, double d) {
  const double sinAlpha = radius / d;
  const double cosAlpha = std::sqrt(std::max(0.0, 1 - sinAlpha * sinAlpha));
  return 2 * kPi * sinAlpha * sinAlpha / (1 + cosAlpha);
}

/// The shares of a sphere's disc in the texels it covers (summing to 1).
void appendSphereShares(const SphereLight& light, const CubeLattice& lattice, const Vec3& toLight,
                        double d, std::vector<LightTap>& taps) {
  const Vec3 axis = toLight / d;
  const double sinAlpha = light.radius / d;
  const double cosAlpha = std::sqrt(std::max(0.0, 1 - sinAlpha * sinAlpha));
  const double alpha = std::asin(sinAlpha);
  const double texelAngle = 0.5 * kPi / lattice.resolution();

  const int centreTexel = lattice.texelOf(axis);
  // A disc under a microradian (fuzzing found one at 1e-10) is a point: the
  // cell grid cannot resolve it, and its texel holds it to 1e-6 of a texel.
  if (!(alpha > 1e-6)) {
    taps.push_back({centreTexel, 1.0});
    return;
  }
  if (alpha < texelAngle) {
    const auto normals = texelBoundaryNormals(lattice, centreTexel);
    if (std::all_of(normals.begin(), normals.end(),
                    [&](const Vec3& n) { return n.dot(axis) >= sinAlpha; })) {
      taps.push_back({centreTexel, 1.0});  // the whole disc in one texel: exact
      return;
    }
  }
  const size_t start = taps.size();
  if (alpha <= 2 * texelAngle)
    capByCells(lattice, axis, cosAlpha, sinAlpha, alpha, texelAngle, taps);
  else
    capByTexels(lattice, axis, cosAlpha, sinAlpha, taps);
  double sum = 0;
  for (size_t i = start; i < taps.size(); ++i) sum += taps[i].weight;
  if (!(sum > 0)) {
    taps.resize(start);
    taps.push_back({centreTexel, 1.0});
    return;
  }
  for (size_t i = start; i < taps.size(); ++i) taps[i].weight /= sum;
}

}  // namespace

std::string lightGrammarLines(const std::string& indent) {
  std::string lines;
  for (const LightGrammar& g : kLightGrammars)
    lines += concat(indent, g.grammar, ": ", g.meaning, "\n");
  return lines;
}

std::string LocalLight::canonicalSpec() const {
  std::string text = kLocalLightKindNames.name(kind());
  const auto add = [&](double v) {
    if (text.back() != ':') text += ',';
    text += formatNumber(v);
  };
  text += ":";
  for (int i = 0; i < 3; ++i) add(position[i]);
  if (const SphereLight* s = sphere()) add(s->radius);
  if (const SpotLight* s = spot()) {
    for (int i = 0; i < 3; ++i) add(s->axis[i]);
    add(s->halfAngleDegrees);
  }
  if (emission.x() == emission.y() && emission.y() == emission.z())
    add(emission.x());
  else
    for (int i = 0; i < 3; ++i) add(emission[i]);
  return text;
}

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
  try {
    kLocalLightKindNames.parse(spec.substr(0, colon));
  } catch (const ParameterError& e) {
    throw ParameterError(kParameter, spec, concat("'", e.value(), "' ", e.problem()));
  }
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
      values.push_back({formatNumber(parseFiniteNumber(part, kParameter, spec))});
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
      values.back().push_back(formatNumber(a + i * step));
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
    throw ParameterError(
        kParameter, spec,
        concat("is not KIND:NUMBERS with KIND one of ", kLocalLightKindNames.list(),
               " (docs/lighting.md, \"Local lights\")"));
  LocalLight light;
  LocalLightKind kind;
  try {
    kind = kLocalLightKindNames.parse(spec.substr(0, colon));
  } catch (const ParameterError& e) {
    throw ParameterError(kParameter, spec, concat("'", e.value(), "' ", e.problem()));
  }
  std::vector<double> v;
  for (const std::string& part : splitNumbers(spec.substr(colon + 1)))
    v.push_back(parseFiniteNumber(part, kParameter, spec));
  const LightGrammar& g = kLightGrammars[static_cast<size_t>(kind)];
  const size_t before = g.numbersBeforeEmission;
  if (v.size() != before + 1 && v.size() != before + 3)
    throw ParameterError(kParameter, spec, concat("has ", v.size(), " numbers; write ", g.grammar));
  light.position = Vec3(v[0], v[1], v[2]);
  if (kind == LocalLightKind::Sphere) light.shape = SphereLight{v[3]};
  if (kind == LocalLightKind::Spot) light.shape = SpotLight{Vec3(v[3], v[4], v[5]), v[6]};
  light.emission = emissionFrom(v, before);
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

void validateLocalLight(LocalLight& light) {
  if (light.spec.empty()) light.spec = light.canonicalSpec();
  const auto refuse = [&](const std::string& problem) {
    throw ParameterError(kParameter, light.spec, problem);
  };
  // Bounds that keep every square and product of the relight finite in float.
  if (!light.position.allFinite() || light.position.cwiseAbs().maxCoeff() > kMaxLightCoordinate)
    refuse(concat("its position must be finite, within +-", kMaxLightCoordinate));
  if (!light.emission.allFinite() || light.emission.minCoeff() < 0 ||
      light.emission.maxCoeff() > kMaxLightEmission)
    refuse(concat(light.sphere() ? "its radiance" : "its intensity", " must be finite and in [0, ",
                  kMaxLightEmission, "]"));
  if (const SphereLight* sphere = light.sphere();
      sphere && !(sphere->radius > 0 && sphere->radius <= kMaxLightCoordinate))
    refuse(concat("its radius must be finite and in (0, ", kMaxLightCoordinate, "]"));
  if (SpotLight* spot = std::get_if<SpotLight>(&light.shape)) {
    if (!spot->axis.allFinite() || !(spot->axis.norm() > 0))
      refuse("its direction DX,DY,DZ is zero or not finite");
    // Normalised once: a spec that holds a unit axis reads back unchanged.
    if (std::abs(spot->axis.squaredNorm() - 1) > 4 * std::numeric_limits<double>::epsilon())
      spot->axis.normalize();
    if (!(spot->halfAngleDegrees > 0 && spot->halfAngleDegrees <= 90))
      refuse("its half angle must be in (0, 90] degrees");
  }
}

double lightIrradiance(const LocalLight& light, const Vec3& point) {
  const Vec3 toLight = light.position - point;
  const double d2 = toLight.squaredNorm();
  if (const SphereLight* sphere = light.sphere())
    return d2 > sphere->radius * sphere->radius ? sphereSolidAngle(sphere->radius, std::sqrt(d2))
                                                : -1;
  const double irradiance = 1 / d2;  // inverse square law, per unit intensity
  if (!(d2 > 0 && irradiance <= kMaxIrradiancePerIntensity)) return -1;  // on the point
  const SpotLight* spot = light.spot();
  return spot ? irradiance * spotFalloff(*spot, -toLight / std::sqrt(d2)) : irradiance;
}

bool appendDirectionTaps(const LocalLight& light, const CubeLattice& lattice, const Vec3& point,
                         std::vector<LightTap>& taps) {
  const Vec3 toLight = light.position - point;
  const double d2 = toLight.squaredNorm();
  if (const SphereLight* sphere = light.sphere()) {
    if (!(d2 > sphere->radius * sphere->radius)) return false;
    appendSphereShares(*sphere, lattice, toLight, std::sqrt(d2), taps);
    return true;
  }
  if (!(d2 > 0 && 1 / d2 <= kMaxIrradiancePerIntensity)) return false;
  for (const BilinearTap& tap : lattice.bilinearTaps(toLight))
    if (tap.weight != 0) taps.push_back({tap.texel, tap.weight});
  return true;
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
