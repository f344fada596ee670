#include "relight/lamp_light.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <limits>
#include <numbers>
#include <optional>

#include "core/error.h"
#include "core/overloaded.h"
#include "relight/shadow_ray_batch.h"
#include "relight/sphere_lamp.h"

namespace acpca {

namespace {

Vec3 vec3At(const std::vector<float>& values, long long i) {
  return {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
}

/// Where one sample's shadow ray to a lamp runs and what it brings if the
/// lamp is seen: weight x E x cos x f/albedo (0: below a horizon, or no light).
struct LampRay {
  Eigen::Vector3f origin, direction;
  float distance = 0;
  double light = 0;
};

LampRay lampRay(const TransportHeader& h, const LocalLight& lamp, long long s) {
  const LampGeometry& g = h.lamps;
  const Vec3 origin = vec3At(g.origin, s), n = vec3At(g.normal, s),
             ng = vec3At(g.geometricNormal, s);
  const Vec3 toLamp = lamp.position - origin;
  const double distance = toLamp.norm();
  const Vec3 direction = toLamp / distance;
  LampRay ray;
  // Above both horizons, as the precompute's shadow rays (precompute/shadow_rays.h).
  const double cosine = n.dot(direction);
  if (!(cosine > 0 && ng.dot(direction) > 0)) return ray;
  const double irradiance = lightIrradiance(lamp, origin);
  if (irradiance <= 0) return ray;
  const Vec3 toViewer = (h.camera.eye - origin).normalized();
  ray.light = g.weight[s] * irradiance * cosine *
              brdfShape(g.materials[g.material[s]], n, g.tangentAt(s), toViewer, direction);
  ray.origin = origin.cast<float>();
  ray.direction = direction.cast<float>();
  // Stopped short of the lamp: what lies beyond it casts no shadow.
  ray.distance = static_cast<float>(distance * (1 - 1e-6));
  return ray;
}

/// A point or spot lamp's light on rows [first, end), added to
/// acc[row - first]: a shadow ray per sample.
long long addPointLamp(const TransportHeader& h, const SceneOccluder& occluder,
                       const LocalLight& lamp, long long first, long long end,
                       std::vector<Rgb>& acc) {
  const LampGeometry& g = h.lamps;
  std::vector<double> rowLight(static_cast<size_t>(end - first), 0.0);
  ShadowRayBatch batch(occluder, g.rayEpsilon,
                       [&](std::int64_t r, double light) { rowLight[r - first] += light; });
  for (long long r = first; r < end; ++r)
    for (long long s = g.sampleStart[r]; s < g.sampleStart[r + 1]; ++s) {
      const LampRay ray = lampRay(h, lamp, s);
      if (ray.light > 0) batch.add(ray.origin, ray.direction, ray.distance, r, ray.light);
    }
  batch.flush();
  for (long long r = first; r < end; ++r) acc[r - first] += rowLight[r - first] * lamp.emission;
  return batch.rays();
}

/// A distant disc too small to cast a penumbra (kPointDiscRadius), lit as a
/// point at infinity of its power on rows [first, end): a shadow ray per
/// sample along its direction, weight x cos x f/albedo x L Omega.
long long addDistantPoint(const TransportHeader& h, const SceneOccluder& occluder,
                          const MapSource& disc, long long first, long long end,
                          std::vector<Rgb>& acc) {
  const LampGeometry& g = h.lamps;
  const Vec3 direction = disc.direction.normalized();
  const Eigen::Vector3f towards = direction.cast<float>();
  std::vector<double> rowLight(static_cast<size_t>(end - first), 0.0);
  ShadowRayBatch batch(occluder, g.rayEpsilon,
                       [&](std::int64_t r, double light) { rowLight[r - first] += light; });
  for (long long r = first; r < end; ++r)
    for (long long s = g.sampleStart[r]; s < g.sampleStart[r + 1]; ++s) {
      const Vec3 origin = vec3At(g.origin, s), n = vec3At(g.normal, s);
      const double cosine = n.dot(direction);
      if (!(cosine > 0 && vec3At(g.geometricNormal, s).dot(direction) > 0)) continue;
      const Vec3 toViewer = (h.camera.eye - origin).normalized();
      const double light =
          g.weight[s] * cosine *
          brdfShape(g.materials[g.material[s]], n, g.tangentAt(s), toViewer, direction);
      batch.add(origin.cast<float>(), towards, std::numeric_limits<float>::infinity(), r, light);
    }
  batch.flush();
  const double half = std::sin(0.5 * disc.radius);
  const Rgb power = disc.radiance * (4 * std::numbers::pi * half * half);  // L 2 pi (1 - cos a)
  for (long long r = first; r < end; ++r) acc[r - first] += rowLight[r - first] * power;
  return batch.rays();
}

}  // namespace

std::string exactLampsUnavailable(const TransportHeader& h, bool model) {
  const std::string again =
      model ? "precompute the transport again and compress (or build) it" : "precompute it again";
  if (h.isLightSet()) return "a captured light set holds no surfaces to cast shadows";
  if (h.lamps.empty())
    return concat("it was made before files held their surfaces and camera samples; ", again,
                  " for exact lamps");
  if (h.bounces > 0)
    return "its rows hold bounced light, which a lamp takes from T (the bounced part is not "
           "stored apart)";
  return "";
}

std::string latticeLampsWarning(const std::string& path, const std::string& why) {
  return concat(path, ": lamps are lit through the lattice (their shadow edges come out ",
                "stepped): ", why, "; --light-mode lattice asks for it without this warning");
}

int parseSphereLampRays(const std::string& text) {
  const ParameterError refused("lamp rays", text, "is not a square from 4 to 256 (4, 9, 16, ...)");
  size_t used = 0;
  int rays = 0;
  try {
    rays = std::stoi(text, &used);
  } catch (const std::exception&) {
    throw refused;
  }
  const int side = static_cast<int>(std::lround(std::sqrt(double(rays))));
  if (used != text.size() || side < 2 || side * side != rays || rays > kMaxSphereLampRays)
    throw refused;
  return rays;
}

std::vector<float> ExactLamps::relight(const std::vector<LocalLight>& lights, int sphereRays,
                                       const std::vector<MapSource>& discs) const {
  std::call_once(built_, [&] { occluder_ = std::make_unique<SceneOccluder>(header_.lamps); });
  const long long rows = header_.rows();
  std::vector<float> out(3 * static_cast<size_t>(rows), 0.0f);
  if (lights.empty() && discs.empty()) return out;
  // The lamps in order, then the discs: a cap each, or a point lamp's index.
  // Every kind named: a kind added without its exact light does not compile.
  std::vector<std::optional<CapLamp>> caps;
  for (const LocalLight& light : lights)
    caps.push_back(std::visit(
        Overloaded{[](const PointLight&) -> std::optional<CapLamp> { return std::nullopt; },
                   [](const SpotLight&) -> std::optional<CapLamp> { return std::nullopt; },
                   [&](const SphereLight& sphere) -> std::optional<CapLamp> {
                     return CapLamp::sphere(light, sphere);
                   }},
        light.shape));
  std::vector<const MapSource*> points;  // discs too small for a penumbra
  for (const MapSource& disc : discs)
    if (disc.radius < kPointDiscRadius)
      points.push_back(&disc);
    else
      caps.push_back(CapLamp::distant(disc));
  // Caps probe first: a row's rays depend on its neighbours' probes.
  std::vector<std::vector<LampSight>> sight(caps.size());
  for (size_t i = 0; i < caps.size(); ++i)
    if (caps[i]) sight[i] = sphereLampSight(header_, *occluder_, *caps[i], rays_);
  // Each row sums its lamps in order, then its samples in order, whatever
  // the blocks: the same values for any thread count.
  tbb::parallel_for(tbb::blocked_range<long long>(0, rows, 256), [&](const auto& range) {
    std::vector<Rgb> acc(static_cast<size_t>(range.size()), Rgb::Zero());
    long long rays = 0;
    for (size_t i = 0; i < caps.size(); ++i)
      rays += caps[i]
                  ? addSphereLamp(header_, *occluder_, *caps[i], sight[i], sphereRays,
                                  range.begin(), range.end(), acc)
                  : addPointLamp(header_, *occluder_, lights[i], range.begin(), range.end(), acc);
    for (const MapSource* point : points)
      rays += addDistantPoint(header_, *occluder_, *point, range.begin(), range.end(), acc);
    rays_ += rays;
    for (long long r = range.begin(); r < range.end(); ++r)
      for (int c = 0; c < 3; ++c)
        out[3 * r + c] = static_cast<float>(header_.albedo[3 * r + c] * acc[r - range.begin()][c]);
  });
  return out;
}

std::vector<float> relightLocalLights(
    const std::vector<LocalLight>& lights, const LampSettings& settings, const ExactLamps* exact,
    const std::function<std::vector<float>(const std::vector<LocalLight>&)>& lattice,
    const std::function<void()>& warnOnce) {
  if (settings.mode == LampMode::Lattice || lights.empty()) return lattice(lights);
  if (!exact) {
    warnOnce();
    return lattice(lights);
  }
  return exact->relight(lights, settings.sphereRays);
}

}  // namespace acpca
