// A camera that frames a scene's bounds, for models whose units and placement
// the user does not know (the Collada duck is in centimetres).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/error.h"
#include "precompute/scene.h"

namespace acpca {

Eigen::AlignedBox3d framedBounds(const Scene& scene) {
  Eigen::AlignedBox3d all, solid;
  const auto add = [&](const Eigen::AlignedBox3d& box) {
    all.extend(box);
    // Flat objects (floors, backdrops) would make a model a speck on them.
    if ((box.sizes().array() > 1e-9 * box.sizes().maxCoeff()).all()) solid.extend(box);
  };
  for (const auto& m : scene.meshes) {
    Eigen::AlignedBox3d box;
    for (const auto& v : m.vertices) box.extend(v.cast<double>());
    if (!box.isEmpty()) add(box);
  }
  for (const auto& s : scene.spheres)
    add({s.center - Vec3::Constant(s.radius), s.center + Vec3::Constant(s.radius)});
  return solid.isEmpty() ? all : solid;
}

Camera frameCamera(const Scene& scene, const Vec3& fromDirection, double margin) {
  const Eigen::AlignedBox3d bounds = framedBounds(scene);
  if (bounds.isEmpty()) throw UserError(concat("scene ", scene.name, ": nothing to frame"));
  if (!(fromDirection.norm() > 0) || !fromDirection.allFinite())
    throw ParameterError("camera direction", fromDirection.transpose(), "is not a direction");
  Camera camera = scene.camera;
  const Vec3 centre = bounds.center();
  const double radius = std::max(0.5 * bounds.diagonal().norm(), 1e-9);
  // The bounding sphere fits inside the narrower of the two fields of view.
  const double halfVertical = 0.5 * camera.fovDegrees * std::numbers::pi / 180;
  const double aspect = double(camera.size.width) / camera.size.height;
  const double halfHorizontal = std::atan(std::tan(halfVertical) * aspect);
  const double distance = margin * radius / std::sin(std::min(halfVertical, halfHorizontal));
  const Vec3 d = fromDirection.normalized();
  camera.target = centre;
  camera.eye = centre + distance * d;
  camera.up = std::abs(d.y()) > 0.99 ? Vec3(0, 0, -1) : Vec3(0, 1, 0);
  return camera;
}

void applyCameraSpec(Scene& scene, const std::string& spec) {
  if (spec.empty()) return;
  Vec3 direction = scene.camera.eye - scene.camera.target;  // "auto": the scene's own view
  if (spec != "auto") {
    double theta = 0, phi = 0;
    char extra = 0;
    if (std::sscanf(spec.c_str(), "auto:%lf,%lf%c", &theta, &phi, &extra) != 2 ||
        !std::isfinite(theta) || !std::isfinite(phi))
      throw ParameterError("camera", spec, "expected auto or auto:THETA,PHI (degrees)");
    direction = directionFromAngles(theta * std::numbers::pi / 180, phi * std::numbers::pi / 180);
  }
  scene.camera = frameCamera(scene, direction);
}

}  // namespace acpca
