#include "relight/lamp_light.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/error.h"

namespace acpca {

namespace {

Vec3 vec3At(const std::vector<float>& values, long long i) {
  return {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
}

/// One traced sample's light from the lamps, per channel: weight x E x cos x
/// f/albedo where the sample sees the lamp.
Rgb sampleLight(const TransportHeader& h, const SceneOccluder& occluder,
                const std::vector<const LocalLight*>& lamps, long long s) {
  const LampGeometry& g = h.lamps;
  const Vec3 origin = vec3At(g.origin, s), n = vec3At(g.normal, s),
             ng = vec3At(g.geometricNormal, s);
  const Vec3 toViewer = (h.camera.eye - origin).normalized();
  const Material& material = g.materials[g.material[s]];
  Rgb light = Rgb::Zero();
  for (const LocalLight* lamp : lamps) {
    const Vec3 toLamp = lamp->position - origin;
    const double distance = toLamp.norm();
    const Vec3 direction = toLamp / distance;
    // Above both horizons, as the precompute's shadow rays (precompute/shadow_rays.h).
    const double cosine = n.dot(direction);
    if (!(cosine > 0 && ng.dot(direction) > 0)) continue;
    const double irradiance = lightIrradiance(*lamp, origin);
    if (irradiance <= 0) continue;
    // Stopped short of the lamp: what lies beyond it casts no shadow.
    if (occluder.blocked(origin.cast<float>(), direction.cast<float>(), g.rayEpsilon,
                         static_cast<float>(distance * (1 - 1e-6))))
      continue;
    light += (irradiance * cosine * brdfShape(material, n, toViewer, direction)) * lamp->emission;
  }
  return g.weight[s] * light;
}

}  // namespace

bool litExactly(const LocalLight& light) {
  return !light.sphere();
}

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
  return concat(path, ": point and spot lamps are lit through the lattice (their shadow edges ",
                "come out stepped): ", why,
                "; --light-mode lattice asks for it without this warning");
}

std::vector<float> ExactLamps::relight(const std::vector<LocalLight>& lights) const {
  std::call_once(built_, [&] { occluder_ = std::make_unique<SceneOccluder>(header_.lamps); });
  std::vector<const LocalLight*> lamps;
  for (const LocalLight& light : lights)
    if (litExactly(light)) lamps.push_back(&light);
  const long long rows = header_.rows();
  std::vector<float> out(3 * static_cast<size_t>(rows), 0.0f);
  if (lamps.empty()) return out;
  const LampGeometry& g = header_.lamps;
  tbb::parallel_for(tbb::blocked_range<long long>(0, rows, 64), [&](const auto& range) {
    for (long long r = range.begin(); r < range.end(); ++r) {
      Rgb light = Rgb::Zero();
      for (long long s = g.sampleStart[r]; s < g.sampleStart[r + 1]; ++s)
        light += sampleLight(header_, *occluder_, lamps, s);
      for (int c = 0; c < 3; ++c)
        out[3 * r + c] = static_cast<float>(header_.albedo[3 * r + c] * light[c]);
    }
  });
  return out;
}

std::vector<float> relightLocalLights(
    const std::vector<LocalLight>& lights, LampMode mode, const ExactLamps* exact,
    const std::function<std::vector<float>(const std::vector<LocalLight>&)>& lattice,
    const std::function<void()>& warnOnce) {
  const bool anyLamp = std::any_of(lights.begin(), lights.end(), litExactly);
  if (mode == LampMode::Lattice || !anyLamp) return lattice(lights);
  if (!exact) {
    warnOnce();
    return lattice(lights);
  }
  std::vector<LocalLight> rest;
  std::copy_if(lights.begin(), lights.end(), std::back_inserter(rest),
               [](const LocalLight& l) { return !litExactly(l); });
  std::vector<float> rows = exact->relight(lights);
  if (!rest.empty()) {
    const std::vector<float> more = lattice(rest);
    for (size_t i = 0; i < rows.size(); ++i) rows[i] += more[i];
  }
  return rows;
}

}  // namespace acpca
