// Anisotropic materials and tangents in scene files (docs/scenes.md,
// "Materials" and "Tangents"): Cycles' anisotropy mapping, the two alphas
// given directly, the rotation, each bad value refused naming the object,
// the field and the range, and a mesh's tangents from the file (glTF
// TANGENT), from its texture coordinates, or the stated fallback with a
// warning.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/error.h"
#include "core/warning.h"
#include "precompute/embree_scene.h"
#include "precompute/scene.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

using test::TempDir;

const char* kCamera =
    R"("camera": {"eye": [0, 5, 0.1], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40})";

std::string sceneWith(const TempDir& dir, const std::string& objects) {
  const std::string path = dir.file("scene.json");
  std::ofstream(path) << "{" << kCamera << R"(, "objects": [)" << objects << "]}";
  return path;
}

std::string planeWith(const std::string& material) {
  return R"({"shape": "plane", "center": [0, 0, 0], "normal": [0, 1, 0], "size": 2, "material": )" +
         material + "}";
}

TEST(AnisotropicScenes, GgxAnisotropyFollowsCyclesAndTheAlphasMayBeGiven) {
  const TempDir dir;
  const Scene cycles = loadSceneJson(sceneWith(
      dir, planeWith(R"({"type": "ggx", "albedo": [1, 1, 1], "specular": 1, "roughness": 0.2,
                         "anisotropy": 0.8, "rotation": 30})")));
  const Material& m = cycles.meshes[0].material;
  const double aspect = std::sqrt(1 - 0.9 * 0.8);
  EXPECT_DOUBLE_EQ(m.alphaU(), 0.2 / aspect);
  EXPECT_DOUBLE_EQ(m.alphaV(), 0.2 * aspect);
  EXPECT_EQ(m.rotationDegrees, 30);
  EXPECT_TRUE(m.anisotropic());
  const Scene axes =
      loadSceneJson(sceneWith(dir, planeWith(R"({"type": "ggx", "albedo": [1, 1, 1], "specular": 1,
                         "roughness_u": 0.05, "roughness_v": 0.4})")));
  EXPECT_EQ(axes.meshes[0].material.alphaU(), 0.05);
  EXPECT_EQ(axes.meshes[0].material.alphaV(), 0.4);
  const Scene as = loadSceneJson(sceneWith(
      dir, planeWith(R"({"type": "ashikhmin-shirley", "albedo": [1, 1, 1], "specular": 0.05,
                         "nu": 40, "nv": 10})")));
  EXPECT_EQ(as.meshes[0].material.type, Material::Type::AshikhminShirley);
  EXPECT_EQ(as.meshes[0].material.nu, 40);
  EXPECT_EQ(as.meshes[0].material.nv, 10);
  EXPECT_EQ(describeMaterial(as.meshes[0].material), "ashikhmin-shirley rs 0.05 nu 40 nv 10");
}

void expectRefused(const TempDir& dir, const std::string& material, const std::string& needle,
                   const std::string& range) {
  try {
    loadSceneJson(sceneWith(dir, planeWith(material)));
    FAIL() << "accepted " << material;
  } catch (const UserError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("objects[0].material." + needle), std::string::npos) << what;
    EXPECT_NE(what.find(range), std::string::npos) << what;
  }
}

TEST(AnisotropicScenes, BadValuesAreRefusedNamingTheObjectTheFieldAndTheRange) {
  const TempDir dir;
  const std::string as = R"({"type": "ashikhmin-shirley", "albedo": [1, 1, 1], "specular": 0.1, )";
  expectRefused(dir, as + R"("nu": 0, "nv": 10})", "nu", "outside (0, 1e6]");
  expectRefused(dir, as + R"("nu": 40, "nv": -3})", "nv", "outside (0, 1e6]");
  const std::string ggx =
      R"({"type": "ggx", "albedo": [1, 1, 1], "specular": 1, "roughness": 0.3, )";
  expectRefused(dir, ggx + R"("anisotropy": 1})", "anisotropy", "outside [0, 1)");
  expectRefused(dir, ggx + R"("anisotropy": -0.2})", "anisotropy", "outside [0, 1)");
  expectRefused(dir, ggx + R"("anisotropy": 0.5, "rotation": 4000})", "rotation",
                "outside [-3600, 3600]");
  expectRefused(dir, R"({"type": "diffuse", "albedo": [1, 1, 1], "nu": 40})", "nu",
                "only ashikhmin-shirley");
  expectRefused(dir, R"({"type": "phong", "albedo": [1, 1, 1], "specular": 0.1, "exponent": 5,
                        "rotation": 10})",
                "rotation", "only ashikhmin-shirley, ggx");
  expectRefused(dir, R"({"type": "ggx", "albedo": [1, 1, 1], "specular": 1,
                        "roughness_u": 0.1, "roughness_v": 0})",
                "roughness_v", "outside [0.001");
}

/// The tangent where a ray straight down meets the scene's first mesh.
Vec3 tangentFromAbove(const Scene& scene, const Vec3& at) {
  const EmbreeScene embree(scene);
  const EmbreeScene::Hit hit = embree.intersect(at + Vec3(0, 3, 0), {0, -1, 0});
  EXPECT_GE(hit.material, 0);
  return hit.tangent;
}

TEST(AnisotropicScenes, MeshTangentsComeFromTheFileTheirUvsOrTheFallbackWithAWarning) {
  const TempDir dir;
  // One triangle in the plane y = 0 whose file tangent is +Z (not the
  // fallback +X): glTF's TANGENT.
  std::ofstream(dir.file("t.gltf"))
      << R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"scene":0,"nodes":[{"mesh":0}],)"
      << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TANGENT":2},"indices":3}]}],)"
      << R"("buffers":[{"byteLength":128,"uri":"data:application/octet-stream;base64,)"
      << "AAAAAAAAAAAAAAAAAAAAAAAAAAAAAIA/"
         "AACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8A"
      << "AAAAAAAAAAAAAAAAAIA/AACAPwAAAAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAIA/AAABAAIAAAA="
      << R"("}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},)"
      << R"({"buffer":0,"byteOffset":36,"byteLength":36},{"buffer":0,"byteOffset":72,"byteLength":48},)"
      << R"({"buffer":0,"byteOffset":120,"byteLength":6}],"accessors":[)"
      << R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]},)"
      << R"({"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"},)"
      << R"({"bufferView":2,"componentType":5126,"count":3,"type":"VEC4"},)"
      << R"({"bufferView":3,"componentType":5123,"count":3,"type":"SCALAR"}]})";
  // The same triangle in OBJ: u runs along +Z, and without coordinates.
  std::ofstream(dir.file("uv.obj")) << "v 0 0 0\nv 0 0 1\nv 1 0 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                       "vn 0 1 0\nf 1/1/1 2/2/1 3/3/1\n";
  std::ofstream(dir.file("bare.obj")) << "v 0 0 0\nv 0 0 1\nv 1 0 0\nvn 0 1 0\nf 1//1 2//1 3//1\n";
  const std::string brushed =
      R"("material": {"type": "ashikhmin-shirley", "albedo": [1, 1, 1], "specular": 0.1, "nu": 40, "nv": 10})";
  std::vector<std::string> warnings;
  const auto previous = setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
  const Vec3 inside(0.2, 0, 0.2);
  const Vec3 fromFile = tangentFromAbove(
      loadSceneJson(sceneWith(dir, R"({"mesh": "t.gltf", )" + brushed + "}")), inside);
  const Vec3 fromUvs = tangentFromAbove(
      loadSceneJson(sceneWith(dir, R"({"mesh": "uv.obj", )" + brushed + "}")), inside);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  // Turned by the object's transform: 90 degrees about +Y takes +Z to +X.
  const Vec3 turned = tangentFromAbove(
      loadSceneJson(sceneWith(
          dir, R"({"mesh": "uv.obj", "transform": {"rotate_y_deg": 90}, )" + brushed + "}")),
      Vec3(0.2, 0, -0.2));
  const Vec3 fallback = tangentFromAbove(
      loadSceneJson(sceneWith(dir, R"({"mesh": "bare.obj", )" + brushed + "}")), inside);
  setWarningHandler(previous);
  EXPECT_NEAR(std::abs(fromFile.z()), 1, 1e-6) << fromFile.transpose();
  EXPECT_NEAR(std::abs(fromUvs.z()), 1, 1e-6) << fromUvs.transpose();
  EXPECT_NEAR(std::abs(turned.x()), 1, 1e-6) << turned.transpose();
  EXPECT_NEAR(std::abs(fallback.x()), 1, 1e-6) << fallback.transpose();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("bare.obj"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("no usable tangent"), std::string::npos) << warnings[0];
}

}  // namespace
}  // namespace acpca
