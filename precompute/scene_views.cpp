#include "precompute/scene_views.h"

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "core/error.h"
#include "precompute/embree_scene.h"

namespace acpca {

std::string viewName(size_t k) {
  std::ostringstream name;
  name << "v" << std::setw(2) << std::setfill('0') << k;
  return name.str();
}

std::string viewOutputPath(const std::string& out, size_t k, size_t views) {
  if (views <= 1) return out;
  const std::filesystem::path path(out);
  return (path.parent_path() /
          (path.stem().string() + "_" + viewName(k) + path.extension().string()))
      .string();
}

void refuseBlindViews(const Scene& scene) {
  if (scene.views.size() <= 1) return;
  const EmbreeScene embree(scene);
  for (size_t k = 0; k < scene.views.size(); ++k) {
    const Camera& c = scene.views[k];
    const GBuffer gbuffer = renderGBuffer(embree, c, 1);
    const bool sees = std::any_of(gbuffer.samples.begin(), gbuffer.samples.end(),
                                  [](const PixelSample& s) { return s.material >= 0; });
    if (!sees)
      throw UserError(concat(scene.name, ": view ", k, " (camera at ", c.eye.x(), ",", c.eye.y(),
                             ",", c.eye.z(), " toward ", c.target.x(), ",", c.target.y(), ",",
                             c.target.z(), ") sees nothing of the scene"));
  }
}

}  // namespace acpca
