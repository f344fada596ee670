#include "precompute/sphere_light_reference.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "precompute/embree_scene.h"

namespace acpca {

namespace {

/// The light reflected by one camera sample: stratified directions in the
/// light's cone (cos theta uniform: equal solid angle), each unoccluded one
/// adding radiance x f x cos x (cone solid angle / count).
Eigen::Vector3d shadeSample(const EmbreeScene& embree, const PixelSample& ps,
                            const SphereLightSource& light, int strata) {
  const Vec3 origin = ps.origin.cast<double>(), n = ps.normal.cast<double>();
  const Vec3 toViewer = ps.toViewer.cast<double>(), geometric = ps.geometricNormal.cast<double>();
  const Vec3 toCentre = light.centre - origin;
  const double d2 = toCentre.squaredNorm();
  if (!(d2 > light.radius * light.radius)) return Eigen::Vector3d::Zero();
  const Vec3 axis = toCentre.normalized();
  const double sinAlpha2 = light.radius * light.radius / d2;
  const double oneMinusCos = sinAlpha2 / (1 + std::sqrt(1 - sinAlpha2));
  const double share = 2 * std::numbers::pi * oneMinusCos / (strata * strata);
  const Vec3 helper = std::abs(axis.y()) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 u = axis.cross(helper).normalized(), v = axis.cross(u);
  const Material& material = embree.materials()[ps.material];
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  double sum = 0;
  for (int a = 0; a < strata; ++a)
    for (int b = 0; b < strata; ++b) {
      const double cosT = 1 - (a + 0.5) / strata * oneMinusCos;
      const double sinT = std::sqrt(std::max(0.0, 1 - cosT * cosT));
      const double phi = 2 * std::numbers::pi * (b + 0.5 * ((a & 1) + 0.5)) / strata;
      const Vec3 w = cosT * axis + sinT * (std::cos(phi) * u + std::sin(phi) * v);
      const double cosine = n.dot(w);
      if (cosine <= 0 || geometric.dot(w) <= 0) continue;  // as the transport: both horizons
      // To the light's near surface: t = w.c - sqrt((w.c)^2 - |c|^2 + r^2).
      const double along = w.dot(toCentre);
      const double t =
          along - std::sqrt(std::max(0.0, along * along - d2 + light.radius * light.radius));
      RTCRay ray{};
      ray.org_x = float(origin.x()), ray.org_y = float(origin.y()), ray.org_z = float(origin.z());
      ray.dir_x = float(w.x()), ray.dir_y = float(w.y()), ray.dir_z = float(w.z());
      ray.tnear = embree.rayEpsilon(), ray.tfar = float(t), ray.mask = ~0u;
      rtcOccluded1(embree.handle(), &context, &ray);
      if (ray.tfar < 0) continue;  // occluded
      sum += brdfShape(material, n, ps.tangent.cast<double>(), toViewer, w) * cosine;
    }
  return sum * share * ps.albedo.cast<double>().cwiseProduct(light.radiance);
}

}  // namespace

std::vector<float> renderSphereLightReference(const Scene& scene, const SphereLightSource& light,
                                              int samplesPerPixel, int lightSamples) {
  ACPCA_CHECK(samplesPerPixel >= 1 && lightSamples >= 1, samplesPerPixel, " ", lightSamples);
  const EmbreeScene embree(scene);
  const GBuffer gbuffer = renderGBuffer(embree, scene.camera, samplesPerPixel);
  const int strata = std::max(1, static_cast<int>(std::lround(std::sqrt(double(lightSamples)))));
  const ImageSize size = scene.camera.size;
  std::vector<Eigen::Vector3d> pixel(static_cast<size_t>(size.pixels()), Eigen::Vector3d::Zero());
  std::vector<char> hit(pixel.size(), 0);
  tbb::parallel_for(0, size.height, [&](int y) {
    for (int x = 0; x < size.width; ++x) {
      int hits = 0;
      for (int s = 0; s < samplesPerPixel; ++s) {
        const PixelSample& ps = gbuffer.at(x, y, s);
        if (ps.material < 0) continue;
        pixel[size_t(y) * size.width + x] += shadeSample(embree, ps, light, strata);
        ++hits;
      }
      if (hits == 0) continue;
      pixel[size_t(y) * size.width + x] /= hits;
      hit[size_t(y) * size.width + x] = 1;
    }
  });
  std::vector<float> rows;
  for (size_t p = 0; p < pixel.size(); ++p)
    if (hit[p])
      rows.insert(rows.end(), {float(pixel[p].x()), float(pixel[p].y()), float(pixel[p].z())});
  return rows;
}

}  // namespace acpca
