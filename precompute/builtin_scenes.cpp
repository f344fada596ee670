// The built-in scenes: the canonical cases of [Mahajan07] (Fig. 7) and the plant of
// its Fig. 1, ready to precompute without any files.
#include <cmath>
#include <functional>
#include <numbers>

#include "core/error.h"
#include "precompute/scene.h"

namespace acpca {

namespace {

Material diffuse(float r, float g, float b) {
  return {Material::Type::Diffuse, {r, g, b}};
}

const Material kGround = diffuse(0.6f, 0.6f, 0.6f);
const Material kBlocker = diffuse(0.7f, 0.35f, 0.25f);

/// A camera looking down at the origin from the front, as for the plane scenes.
Camera overheadCamera() {
  Camera c;
  c.eye = {0, 3.2, 4.4};
  c.target = {0, 0, 0};
  c.fovDegrees = 40;
  return c;
}

Scene sphereScene() {
  Scene s;
  s.name = "sphere";
  s.camera.eye = {0, 0.8, 4.5};
  s.camera.target = {0, 0, 0};
  s.camera.fovDegrees = 30;
  s.spheres.push_back({{0, 0, 0}, 1.0, diffuse(0.5f, 0.5f, 0.5f)});
  return s;
}

Scene phongSphereScene() {
  Scene s = sphereScene();
  s.name = "phong-sphere";
  s.spheres[0].material = {Material::Type::Phong, {0.6f, 0.6f, 0.6f}, 0.5, 100.0};
  return s;
}

/// Inside of a hemispherical bowl (open upwards) standing on the ground.
Scene concaveScene() {
  Scene s{"concave", overheadCamera(), {}, {}, {}, {}};
  s.camera.eye = {0, 3.0, 3.0};
  s.camera.target = {0, 0.4, 0};
  s.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 12, kGround, "ground"));
  TriangleMesh bowl = emptyMesh("bowl", diffuse(0.7f, 0.7f, 0.65f));
  const int rings = 48, segments = 96;
  const double radius = 1.0, centerY = 1.0;
  for (int i = 0; i <= rings; ++i) {
    const double theta = 0.5 * std::numbers::pi * i / rings;  // 0 = bottom, pi/2 = rim
    for (int k = 0; k < segments; ++k) {
      const double phi = 2 * std::numbers::pi * k / segments;
      bowl.vertices.emplace_back(float(radius * std::sin(theta) * std::cos(phi)),
                                 float(centerY - radius * std::cos(theta)),
                                 float(radius * std::sin(theta) * std::sin(phi)));
    }
  }
  for (int i = 0; i < rings; ++i)
    for (int k = 0; k < segments; ++k) {
      const int a = i * segments + k, b = i * segments + (k + 1) % segments;
      // Ring 0 is the bottom point, repeated: a fan there, not a quad strip.
      if (i > 0) bowl.triangles.emplace_back(a, a + segments, b);
      bowl.triangles.emplace_back(b, a + segments, b + segments);
    }
  s.meshes.push_back(std::move(bowl));
  return s;
}

Scene stepScene() {
  Scene s{"step", overheadCamera(), {}, {}, {}, {}};
  s.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 12, kGround, "ground"));
  // A long step: raised by 0.5 over the far half (z < 0) of the ground.
  s.meshes.push_back(makeBox({-6, 0, -6}, {6, 0.5, 0}, kBlocker, "step"));
  return s;
}

Scene grid1dScene() {
  Scene s{"grid1d", overheadCamera(), {}, {}, {}, {}};
  s.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 12, kGround, "ground"));
  TriangleMesh bars = emptyMesh("bars", kBlocker);
  for (int i = -6; i <= 6; ++i)  // thin bars along x, floating at height 0.5
    appendMesh(bars,
               makeBox({-3, 0.45, i * 0.35 - 0.06}, {3, 0.55, i * 0.35 + 0.06}, kBlocker, ""));
  s.meshes.push_back(std::move(bars));
  return s;
}

Scene grid2dScene() {
  Scene s{"grid2d", overheadCamera(), {}, {}, {}, {}};
  s.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 12, kGround, "ground"));
  TriangleMesh blocks = emptyMesh("blocks", kBlocker);
  for (int i = -6; i <= 6; ++i)
    for (int k = -6; k <= 6; ++k)  // small cubes floating at height 0.5
      appendMesh(blocks, makeBox({i * 0.35 - 0.07, 0.43, k * 0.35 - 0.07},
                                 {i * 0.35 + 0.07, 0.57, k * 0.35 + 0.07}, kBlocker, ""));
  s.meshes.push_back(std::move(blocks));
  return s;
}

struct BuiltinEntry {
  BuiltinSceneInfo info;
  std::function<Scene()> make;
};

const std::vector<BuiltinEntry>& registry() {
  static const std::vector<BuiltinEntry> entries = {
      {{"plant", "potted plant of ~300 curved leaves (>50k triangles) on a ground plane"},
       makePlantScene},
      {{"sphere", "diffuse sphere alone, albedo 0.5 (the furnace test)"}, sphereScene},
      {{"phong-sphere", "Phong sphere alone, ks 0.5, s 100 (glossy reflection)"}, phongSphereScene},
      {{"concave", "inside of a hemispherical bowl on a ground plane (self-shadowing)"},
       concaveScene},
      {{"step", "long step blocker over a ground plane (one shadow edge)"}, stepScene},
      {{"grid1d", "row of thin bars floating over a ground plane (1D blocker grid)"}, grid1dScene},
      {{"grid2d", "13x13 small cubes floating over a ground plane (2D blocker grid)"}, grid2dScene},
  };
  return entries;
}

}  // namespace

std::vector<BuiltinSceneInfo> builtinScenes() {
  std::vector<BuiltinSceneInfo> infos;
  for (const auto& e : registry()) infos.push_back(e.info);
  return infos;
}

bool isBuiltinScene(const std::string& name) {
  for (const auto& e : registry())
    if (e.info.name == name) return true;
  return false;
}

Scene makeBuiltinScene(const std::string& name) {
  for (const auto& e : registry())
    if (e.info.name == name) return e.make();
  throw UserError(concat("unknown built-in scene '", name, "' (see `adaptive-cpca scenes`)"));
}

}  // namespace acpca
