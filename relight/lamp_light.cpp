#include "relight/lamp_light.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <utility>

#include "core/error.h"

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
              brdfShape(g.materials[g.material[s]], n, toViewer, direction);
  ray.origin = origin.cast<float>();
  ray.direction = direction.cast<float>();
  // Stopped short of the lamp: what lies beyond it casts no shadow.
  ray.distance = static_cast<float>(distance * (1 - 1e-6));
  return ray;
}

/// One lamp's light on rows [first, end), added to acc[row - first]: the
/// samples' shadow rays in packets, neighbouring pixels' rays together.
void addLamp(const TransportHeader& h, const SceneOccluder& occluder, const LocalLight& lamp,
             long long first, long long end, std::vector<Rgb>& acc) {
  const LampGeometry& g = h.lamps;
  SceneOccluder::Packet packet;
  std::array<std::pair<long long, double>, SceneOccluder::kPacket> pending;  // row, light
  const auto flush = [&] {
    occluder.trace(packet);
    for (int i = 0; i < packet.count; ++i)
      if (!packet.blocked[i]) acc[pending[i].first - first] += pending[i].second * lamp.emission;
    packet.count = 0;
  };
  for (long long r = first; r < end; ++r)
    for (long long s = g.sampleStart[r]; s < g.sampleStart[r + 1]; ++s) {
      const LampRay ray = lampRay(h, lamp, s);
      if (ray.light <= 0) continue;
      const int i = packet.count++;
      packet.ox[i] = ray.origin.x(), packet.oy[i] = ray.origin.y(), packet.oz[i] = ray.origin.z();
      packet.dx[i] = ray.direction.x(), packet.dy[i] = ray.direction.y();
      packet.dz[i] = ray.direction.z();
      packet.nearest[i] = g.rayEpsilon, packet.farthest[i] = ray.distance;
      pending[i] = {r, ray.light};
      if (packet.count == SceneOccluder::kPacket) flush();
    }
  if (packet.count > 0) flush();
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
  // Each row sums its lamps in order, then its samples in order, whatever
  // the blocks: the same values for any thread count.
  tbb::parallel_for(tbb::blocked_range<long long>(0, rows, 256), [&](const auto& range) {
    std::vector<Rgb> acc(static_cast<size_t>(range.size()), Rgb::Zero());
    for (const LocalLight* lamp : lamps)
      addLamp(header_, *occluder_, *lamp, range.begin(), range.end(), acc);
    for (long long r = range.begin(); r < range.end(); ++r)
      for (int c = 0; c < 3; ++c)
        out[3 * r + c] = static_cast<float>(header_.albedo[3 * r + c] * acc[r - range.begin()][c]);
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
