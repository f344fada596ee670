#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <numbers>

#include "core/error.h"
#include "core/warning.h"
#include "precompute/embree_scene.h"
#include "precompute/mesh_import.h"
#include "precompute/scene.h"
#include "tests/render_support.h"

namespace acpca {
namespace {

using test::TempDir;

TEST(BuiltinScenes, AllExistAndAreValid) {
  for (const char* name :
       {"sphere", "plant", "phong-sphere", "concave", "step", "grid1d", "grid2d"}) {
    ASSERT_TRUE(isBuiltinScene(name)) << name;
    const Scene s = makeBuiltinScene(name);
    EXPECT_NO_THROW(s.validate()) << name;
    EXPECT_EQ(s.camera.size.width, 256);
  }
  EXPECT_THROW(makeBuiltinScene("teapot"), UserError);
}

TEST(BuiltinScenes, MakeNoZeroAreaTriangles) {
  // The loader leaves such triangles out; a generator should not make them.
  for (const auto& info : builtinScenes()) {
    const Scene s = makeBuiltinScene(info.name);
    long long degenerate = 0;
    for (const auto& mesh : s.meshes)
      for (const auto& t : mesh.triangles) {
        const Eigen::Vector3f e1 = mesh.vertices[t[1]] - mesh.vertices[t[0]];
        const Eigen::Vector3f e2 = mesh.vertices[t[2]] - mesh.vertices[t[0]];
        if (e1.cross(e2).norm() == 0) ++degenerate;
      }
    EXPECT_EQ(degenerate, 0) << info.name;
  }
}

TEST(BuiltinScenes, PlantIsDetailedAndTheSameEveryTime) {
  const Scene a = makePlantScene(), b = makePlantScene();
  EXPECT_GE(a.triangleCount(), 50000);
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (size_t m = 0; m < a.meshes.size(); ++m)
    EXPECT_EQ(a.meshes[m].vertices, b.meshes[m].vertices);
}

std::string writeFile(const TempDir& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir.file(name)) << text;
  return dir.file(name);
}

const char* kCamera =
    R"("camera": {"eye": [0, 2, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40})";

TEST(SceneJson, ReadsPrimitivesMeshesAndTransforms) {
  TempDir dir;
  writeFile(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4 2\n");
  writeFile(dir, "tri.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const std::string path = writeFile(dir, "scene.json", std::string("{") + kCamera + R"(,
    "objects": [
      {"shape": "sphere", "center": [0, 1, 0], "radius": 0.5,
       "material": {"type": "phong", "albedo": [0.5, 0.5, 0.5], "specular": 0.4, "exponent": 50}},
      {"shape": "plane", "center": [0, 0, 0], "normal": [0, 1, 0], "size": 10,
       "material": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}},
      {"mesh": "tri.obj", "transform": {"scale": 2, "rotate_y_deg": 90, "translate": [1, 0, 0]},
       "material": {"type": "diffuse", "albedo": [1, 0, 0]}},
      {"mesh": "tri.ply", "transform": {"matrix": [1,0,0,5, 0,1,0,0, 0,0,1,0, 0,0,0,1]},
       "material": {"type": "ggx", "albedo": [0, 1, 0], "specular": 0.3, "roughness": 0.2}}]})");
  const Scene s = loadSceneJson(path);
  EXPECT_EQ(s.spheres.size(), 1u);
  EXPECT_EQ(s.spheres[0].material.type, Material::Type::Phong);
  EXPECT_EQ(s.meshes[2].material.type, Material::Type::Ggx);
  EXPECT_EQ(s.meshes[2].material.roughness, 0.2);
  ASSERT_EQ(s.meshes.size(), 3u);
  EXPECT_EQ(s.meshes[1].triangles.size(), 3u);  // a triangle and a triangulated quad
  // scale 2, then 90 degrees about +Y (x -> -z), then +1 in x: (1,0,0) -> (1,0,-2).
  EXPECT_TRUE(s.meshes[1].vertices[1].isApprox(Eigen::Vector3f(1, 0, -2), 1e-6f));
  EXPECT_TRUE(s.meshes[2].vertices[1].isApprox(Eigen::Vector3f(6, 0, 0), 1e-6f));
}

TEST(SceneJson, MeshNormalsComeFromTheFileOrAreMadeSmoothOrFlat) {
  TempDir dir;
  // A quad whose file normals lean towards +x, which the rotation must follow.
  writeFile(dir, "quad.obj",
            "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nvn 0.6 0.8 0\nf 1//1 3//1 2//1\n"
            "f 1//1 4//1 3//1\n");
  writeFile(dir, "bare.obj", "v 0 0 0\nv 1 0 0\nv 1 0 1\nf 1 3 2\n");
  const auto scene = [&](const std::string& objects) {
    return loadSceneJson(writeFile(
        dir, "n.json", std::string("{") + kCamera + R"(, "objects": [)" + objects + "]}"));
  };
  const std::string grey = R"("material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]})";
  const Scene file =
      scene(R"({"mesh": "quad.obj", "transform": {"rotate_y_deg": 90}, )" + grey + "}");
  ASSERT_EQ(file.meshes[0].normals.size(), 6u);
  // (0.6, 0.8, 0) turned 90 degrees about +Y: x -> -z.
  EXPECT_TRUE(file.meshes[0].normals[0].isApprox(Eigen::Vector3f(0, 0.8f, -0.6f), 1e-5f));
  const Scene flat = scene(R"({"mesh": "quad.obj", "normals": "flat", )" + grey + "}");
  EXPECT_TRUE(flat.meshes[0].normals.empty());
  const Scene smooth = scene(R"({"mesh": "quad.obj", "normals": "smooth", )" + grey + "}");
  EXPECT_TRUE(smooth.meshes[0].normals[0].isApprox(Eigen::Vector3f(0, -1, 0), 1e-6f) ||
              smooth.meshes[0].normals[0].isApprox(Eigen::Vector3f(0, 1, 0), 1e-6f));
  // No normals in the file: smooth ones, and a warning that says so.
  std::vector<std::string> warnings;
  const auto previous = setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
  const Scene bare = scene(R"({"mesh": "bare.obj", )" + grey + "}");
  setWarningHandler(previous);
  EXPECT_EQ(bare.meshes[0].normals.size(), 3u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("no vertex normals"), std::string::npos) << warnings[0];
  try {
    scene(R"({"mesh": "quad.obj", "normals": "phong", )" + grey + "}");
    FAIL() << "accepted normals 'phong'";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("normals"), std::string::npos) << e.what();
  }
  EXPECT_THROW(scene(R"({"mesh": "quad.obj", "crease_angle": 200, )" + grey + "}"), UserError);
}

TEST(CameraFraming, TheSceneFillsTheViewFromAnyDirectionAndFloorsAreLeftOut) {
  // A sphere of radius 50 far from the origin, on a floor 1000 wide.
  Scene scene{"framed", {}, {}, {}, {}, {}};
  scene.spheres.push_back({{300, 50, -200}, 50, Material{}});
  scene.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 1000, Material{}, "floor"));
  scene.camera.size = {96, 64};
  scene.camera.fovDegrees = 40;
  EXPECT_TRUE(framedBounds(scene).center().isApprox(Vec3(300, 50, -200)));
  for (const char* spec : {"auto:60,30", "auto:0,0", "auto:85,200"}) {
    Scene s = scene;
    applyCameraSpec(s, spec);
    EXPECT_NO_THROW(s.camera.validate()) << spec;
    EXPECT_TRUE(s.camera.target.isApprox(Vec3(300, 50, -200))) << spec;
    // The bounding sphere (the box's, radius 50 sqrt 3) times 1.05 just fits
    // the vertical field of view, the narrower one here.
    const double distance = (s.camera.eye - s.camera.target).norm();
    EXPECT_NEAR(std::asin(1.05 * 50 * std::sqrt(3.0) / distance) * 180 / std::numbers::pi, 20, 1e-9)
        << spec;
    // Looking down the given direction: the sphere is in the middle of the image.
    const EmbreeScene embree(s);
    const auto hit = embree.intersect(s.camera.eye, s.camera.rayDirection(48, 32));
    EXPECT_EQ(hit.material, 1) << spec;  // the sphere (geometry 1), not the floor
  }
  Scene own = scene;
  own.camera.eye = {300, 50, 100};  // "auto" keeps the scene's own direction (+Z)
  own.camera.target = {300, 50, 0};
  applyCameraSpec(own, "auto");
  EXPECT_TRUE((own.camera.eye - own.camera.target).normalized().isApprox(Vec3(0, 0, 1)));
  EXPECT_THROW(applyCameraSpec(own, "auto:30"), ParameterError);
  EXPECT_THROW(applyCameraSpec(own, "front"), ParameterError);
}

void expectError(const std::string& path, const std::string& needle) {
  try {
    loadSceneJson(path);
    FAIL() << "no error; expected one mentioning " << needle;
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(SceneJson, AnOrbitPlacesItsCamerasFromPlusZTowardPlusXAndAListIsTakenAsIs) {
  TempDir dir;
  const std::string sphere =
      R"({"shape": "sphere", "center": [0,0,0], "radius": 1, "material": {"type": "diffuse", "albedo": [1,1,1]}})";
  const Scene orbit = loadSceneJson(
      writeFile(dir, "orbit.json",
                R"({"cameras": {"orbit": {"target": [1, 2, 3], "radius": 4, "elevation_deg": 30,
          "count": 4, "fov": 35, "width": 20, "height": 10}}, "objects": [)" +
                    sphere + "]}"));
  ASSERT_EQ(orbit.viewCount(), 4u);
  const double c = 4 * std::cos(std::numbers::pi / 6), h = 4 * std::sin(std::numbers::pi / 6);
  const Vec3 target(1, 2, 3);
  const Vec3 expected[4] = {{0, h, c}, {c, h, 0}, {0, h, -c}, {-c, h, 0}};  // +Z, then +X
  for (size_t k = 0; k < 4; ++k) {
    const Camera& view = orbit.views[k];
    EXPECT_LT((view.eye - target - expected[k]).norm(), 1e-12) << k;
    EXPECT_EQ(view.target, target);
    EXPECT_EQ(view.up, Vec3(0, 1, 0));
    EXPECT_EQ(view.size.width, 20);
    EXPECT_EQ(view.fovDegrees, 35);
    EXPECT_EQ(orbit.view(k).camera.eye, view.eye);
    EXPECT_TRUE(orbit.view(k).views.empty());
  }
  EXPECT_EQ(orbit.camera.eye, orbit.views[0].eye);
  const Scene list = loadSceneJson(writeFile(
      dir, "list.json",
      std::string(
          R"({"cameras": [{"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40},
          {"eye": [5, 0, 0], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 20}], "objects": [)") +
          sphere + "]}"));
  ASSERT_EQ(list.viewCount(), 2u);
  EXPECT_EQ(list.views[1].fovDegrees, 20);
  // One camera: one view, the scene itself.
  const Scene one = loadSceneJson(
      writeFile(dir, "one.json", std::string("{") + kCamera + R"(, "objects": [)" + sphere + "]}"));
  EXPECT_EQ(one.viewCount(), 1u);
  EXPECT_TRUE(one.views.empty());
  // Both keys, neither, an empty list, a count of 0, a flat elevation.
  expectError(
      writeFile(dir, "both.json",
                std::string("{") + kCamera + R"(, "cameras": [], "objects": [)" + sphere + "]}"),
      "either 'camera' or 'cameras'");
  expectError(writeFile(dir, "empty.json", R"({"cameras": [], "objects": [)" + sphere + "]}"),
              "cameras: expected 1..");
  expectError(writeFile(dir, "zero.json",
                        R"({"cameras": {"orbit": {"target": [0,0,0], "radius": 4,
                  "elevation_deg": 0, "count": 0, "fov": 35}}, "objects": [)" +
                            sphere + "]}"),
              "count");
  expectError(writeFile(dir, "pole.json",
                        R"({"cameras": {"orbit": {"target": [0,0,0], "radius": 4,
                  "elevation_deg": 90, "count": 2, "fov": 35}}, "objects": [)" +
                            sphere + "]}"),
              "elevation_deg");
}

TEST(SceneJson, ErrorsNameTheKey) {
  TempDir dir;
  const std::string sphere =
      R"({"shape": "sphere", "center": [0,0,0], "radius": 1, "material": {"type": "diffuse", "albedo": [1,1,1]}})";
  expectError(
      writeFile(dir, "a.json", std::string("{") + kCamera + R"(, "objects": [], "extra": 1})"),
      "'extra'");
  expectError(writeFile(dir, "b.json", R"({"objects": [)" + sphere + "]}"), "'camera'");
  expectError(writeFile(dir, "c.json",
                        std::string("{") + kCamera +
                            R"(, "objects": [{"shape": "sphere", "center": [0,0,0], "radius": 1,
               "material": {"type": "diffuse", "albedo": [1,1,1], "shiny": 3}}]})"),
              "'shiny'");
  expectError(writeFile(dir, "d.json",
                        std::string("{") + kCamera +
                            R"(, "objects": [{"shape": "sphere", "center": [0,0], "radius": 1,
               "material": {"type": "diffuse", "albedo": [1,1,1]}}]})"),
              "center");
  expectError(
      writeFile(
          dir, "e.json",
          std::string("{") + kCamera +
              R"(, "objects": [{"shape": "cone", "material": {"type": "diffuse", "albedo": [1,1,1]}}]})"),
      "cone");
  expectError(writeFile(dir, "f.json",
                        std::string("{") + kCamera +
                            R"(, "objects": [{"shape": "sphere", "center": [0,0,0], "radius": 1,
               "material": {"type": "phong", "albedo": [1,1,1], "specular": 2, "exponent": 10}}]})"),
              "specular");
  expectError(writeFile(dir, "f2.json",
                        std::string("{") + kCamera +
                            R"(, "objects": [{"shape": "sphere", "center": [0,0,0], "radius": 1,
               "material": {"type": "ggx", "albedo": [1,1,1], "specular": 1, "roughness": 0}}]})"),
              "roughness");
  expectError(writeFile(dir, "g.json", "{not json"), "not valid JSON");
  expectError(
      writeFile(
          dir, "h.json",
          R"({"camera": {"eye": [0,0,0], "target": [0,0,0], "up": [0,1,0], "fov": 40}, "objects": [)" +
              sphere + "]}"),
      "eye and target coincide");
  expectError(
      writeFile(
          dir, "i.json",
          std::string("{") + kCamera +
              R"(, "objects": [{"mesh": "missing.obj", "material": {"type": "diffuse", "albedo": [1,1,1]}}]})"),
      "missing.obj");
  expectError(dir.file("nope.json"), "cannot open");
}

TEST(SceneJson, MeshWithNaNVerticesIsAnError) {
  TempDir dir;
  writeFile(dir, "bad.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string path = writeFile(
      dir, "s.json",
      std::string("{") + kCamera +
          R"(, "objects": [{"mesh": "bad.obj", "material": {"type": "diffuse", "albedo": [1,1,1]}}]})");
  expectError(path, "NaN");
}

// assimp runs in a child process (mesh_import.h): what it returns crosses a
// pipe and is checked here, and its failures come back as messages.
TEST(MeshFiles, AFileWithoutMaterialsOrNormalsCrossesTheImporterWhole) {
  TempDir dir;
  // The fuzz target's first finding: empty arrays (no normals, no texture
  // bytes) crossing the pipe.
  const std::string stl = writeFile(dir, "t.stl",
                                    "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 1 1 0\n"
                                    "   vertex -1 1 0\n   vertex 0 -1 0\n  endloop\n endfacet\n"
                                    "endsolid t\n");
  const auto meshes = loadMeshFile(stl, NormalMode::Flat);
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].triangles.size(), 1u);
  EXPECT_EQ(meshes[0].vertices.size(), 3u);
  EXPECT_TRUE(meshes[0].vertices[1].isApprox(Eigen::Vector3f(-1, 1, 0)));
}

TEST(MeshFiles, WhatTheImporterRefusesOrCannotFinishIsAMessageNamingTheFile) {
  TempDir dir;
  const std::string empty = writeFile(dir, "empty.obj", "");
  try {
    loadMeshFile(empty);
    FAIL() << "an empty file has no mesh";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find(empty), std::string::npos) << e.what();
  }
  const std::string good = writeFile(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  try {
    importModelIsolated(good, 0.0);  // no time at all: the child is stopped
    FAIL() << "a zero time limit cannot be met";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("did not finish"), std::string::npos) << e.what();
  }
  EXPECT_EQ(importModelIsolated(good).parts.at(0).corners.size(), 3u);
}

TEST(MeshFiles, AFileThatMakesTheImporterLoopIsStoppedAtItsTimeLimit) {
  // Found by fuzz_mesh_file: a PLY header cut short ("property fheader")
  // sends assimp's reader into a loop that never ends.
  TempDir dir;
  const std::string ply = writeFile(dir, "loop.ply",
                                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float32 x\n"
                                    "property float32 y\nproperty fheader\n0 0 0\n0 0 1\n0 1 1\n");
  const auto start = std::chrono::steady_clock::now();
  try {
    loadMeshFile(ply, NormalMode::File, kDefaultCreaseDegrees, 1.0);
    SUCCEED() << "this assimp reads it";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find(ply), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  EXPECT_NEAR(defaultImportSeconds(ply), 60.0, 0.01) << "a minute plus a second per MiB";
}

TEST(MeshFiles, TheRawFilesThatOnceCrashedTheCollectorLoad) {
  // Two of Debian's assimp-testmodels segfaulted in the mesh collector: it
  // followed what assimp returned without checking it.
  for (const std::string name : {"WithColor.raw", "WithTexture.raw"}) {
    const std::string path = "/usr/share/assimp/models/RAW/" + name;
    if (!std::ifstream(path)) GTEST_SKIP() << "assimp-testmodels is not installed";
    try {
      const auto meshes = loadMeshFile(path);
      EXPECT_FALSE(meshes.empty()) << path;
    } catch (const UserError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST(SceneJson, ShippedExampleLoads) {
  const Scene s = loadSceneJson(std::string(ACPCA_DATA_DIR) + "/scenes/example.json");
  EXPECT_NO_THROW(s.validate());
  EXPECT_GT(s.meshes.size() + s.spheres.size(), 1u);
}

}  // namespace
}  // namespace acpca
