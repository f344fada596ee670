// Albedo textures and the materials of model files: sRGB decoding, bilinear
// lookup and its orientation, and what assimp hands over from OBJ and glTF.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/warning.h"
#include "precompute/scene.h"
#include "precompute/texture.h"
#include "tests/temp_dir.h"
#include "tests/texture_support.h"

namespace acpca {
namespace {

using test::TempDir;

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

TEST(Texture, SrgbDecodingFollowsItsDefinition) {
  for (int code : {0, 1, 10, 11, 64, 128, 200, 255})
    EXPECT_NEAR(srgbToLinear(code / 255.0f), test::srgbCodeToLinear(code), 1e-6) << code;
  EXPECT_NEAR(srgbToLinear(0.5f), 0.214041, 1e-5);
}

TEST(Texture, BilinearLookupIsExactAtTexelCentresAndWrapsAround) {
  // 2x2, top row A B, bottom row C D: v runs up, so (0.25, 0.75) is A.
  const Eigen::Vector3f a(1, 0, 0), b(0, 1, 0), c(0, 0, 1), d(1, 1, 1);
  const Texture t("t", 2, 2, {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1});
  EXPECT_TRUE(t.sample({0.25f, 0.75f}).isApprox(a));
  EXPECT_TRUE(t.sample({0.75f, 0.75f}).isApprox(b));
  EXPECT_TRUE(t.sample({0.25f, 0.25f}).isApprox(c));
  EXPECT_TRUE(t.sample({0.75f, 0.25f}).isApprox(d));
  EXPECT_TRUE(t.sample({0.5f, 0.75f}).isApprox((a + b) / 2));
  EXPECT_TRUE(t.sample({0.5f, 0.5f}).isApprox((a + b + c + d) / 4));
  // Repeat addressing: one period over and the left edge blends with the right.
  EXPECT_TRUE(t.sample({1.25f, -0.25f}).isApprox(a));
  EXPECT_TRUE(t.sample({0.0f, 0.75f}).isApprox((a + b) / 2));
}

TEST(Texture, FilesAreDecodedAndBadOnesRefusedByName) {
  TempDir dir;
  // RGBA: alpha ignored; 8 bits decoded from sRGB.
  test::writeImage8(dir.file("rgba.png"), 2, 1, 4, {255, 128, 0, 7, 0, 64, 255, 255});
  const auto rgba = loadTexture(dir.file("rgba.png"));
  ASSERT_EQ(rgba->width(), 2);
  EXPECT_NEAR(rgba->texel(0, 0).y(), test::srgbCodeToLinear(128), 1e-6);
  EXPECT_NEAR(rgba->texel(1, 0).y(), test::srgbCodeToLinear(64), 1e-6);
  EXPECT_NEAR(rgba->texel(1, 0).z(), 1, 1e-6);
  // Grey: the one channel is every channel.
  test::writeImage8(dir.file("grey.png"), 1, 1, 1, {200});
  EXPECT_TRUE(loadTexture(dir.file("grey.png"))
                  ->texel(0, 0)
                  .isApprox(Eigen::Vector3f::Constant(float(test::srgbCodeToLinear(200)))));
  // Float textures are linear already; NaN is refused by name.
  {
    auto out = OIIO::ImageOutput::create(dir.file("nan.exr"));
    ASSERT_TRUE(out->open(dir.file("nan.exr"), OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::FLOAT)));
    const float texel[3] = {0.5f, NAN, 0};
    out->write_image(OIIO::TypeDesc::FLOAT, texel);
  }
  try {
    loadTexture(dir.file("nan.exr"));
    FAIL() << "a NaN texel was accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("nan.exr"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadTexture(dir.file("missing.png")), UserError);
  writeText(dir.file("junk.png"), "not an image");
  EXPECT_THROW(loadTexture(dir.file("junk.png")), UserError);
}

TEST(ModelFiles, ObjMaterialsGiveOneMeshEachWithColourTextureAndCoordinates) {
  TempDir dir;
  test::writeImage8(dir.file("red.png"), 1, 1, 3, {255, 0, 0});
  writeText(dir.file("two.mtl"),
            "newmtl painted\nKd 0.5 0.25 1\nmap_Kd red.png\n"
            "newmtl plain\nKd 0.1 0.2 0.3\n"
            "newmtl lost\nKd 0.7 0.7 0.7\nmap_Kd nowhere.png\n");
  writeText(dir.file("two.obj"),
            "mtllib two.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
            "usemtl painted\nf 1/1 2/2 3/3\nusemtl plain\nf 1/1 3/3 4/4\nusemtl lost\nf 1 2 4\n");
  std::vector<std::string> warnings;
  const auto previous = setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
  const std::vector<TriangleMesh> meshes = loadMeshFile(dir.file("two.obj"), NormalMode::Flat);
  setWarningHandler(previous);
  ASSERT_EQ(meshes.size(), 3u);
  const auto named = [&](const std::string& suffix) -> const TriangleMesh& {
    for (const auto& m : meshes)
      if (m.name.size() >= suffix.size() &&
          m.name.compare(m.name.size() - suffix.size(), suffix.size(), suffix) == 0)
        return m;
    throw std::runtime_error("no mesh " + suffix);
  };
  const TriangleMesh& painted = named("/painted");
  EXPECT_TRUE(painted.material.albedo.isApprox(Eigen::Vector3f(0.5f, 0.25f, 1)));
  ASSERT_TRUE(painted.albedoTexture);
  EXPECT_TRUE(painted.albedoTexture->texel(0, 0).isApprox(Eigen::Vector3f(1, 0, 0)));
  ASSERT_EQ(painted.uvs.size(), 3u);
  EXPECT_TRUE(painted.uvs[2].isApprox(Eigen::Vector2f(1, 1)));
  const TriangleMesh& plain = named("/plain");
  EXPECT_TRUE(plain.material.albedo.isApprox(Eigen::Vector3f(0.1f, 0.2f, 0.3f)));
  EXPECT_FALSE(plain.albedoTexture);
  // A texture that is not there: the base colour, and a warning naming the file.
  const TriangleMesh& lost = named("/lost");
  EXPECT_FALSE(lost.albedoTexture);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("nowhere.png"), std::string::npos) << warnings[0];
}

TEST(SceneJson, MaterialsOverrideTheFilesColoursOrOnlyTheirBrdf) {
  TempDir dir;
  test::writeImage8(dir.file("red.png"), 1, 1, 3, {255, 0, 0});
  writeText(dir.file("m.mtl"), "newmtl painted\nKd 0.5 0.5 0.5\nmap_Kd red.png\n");
  writeText(dir.file("m.obj"),
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
            "usemtl painted\nf 1/1 2/2 3/3\n");
  const auto scene = [&](const std::string& object) {
    const std::string camera =
        R"("camera": {"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40})";
    writeText(dir.file("s.json"), "{" + camera + R"(, "objects": [)" + object + "]}");
    return loadSceneJson(dir.file("s.json"));
  };
  // No material: the file's, diffuse.
  Scene s = scene(R"({"mesh": "m.obj"})");
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].albedoTexture);
  EXPECT_TRUE(s.meshes[0].material.albedo.isApprox(Eigen::Vector3f::Constant(0.5f)));
  // A BRDF alone keeps the file's colour and texture.
  s = scene(R"({"mesh": "m.obj", "material": {"type": "ggx", "specular": 0.3, "roughness": 0.2}})");
  EXPECT_EQ(s.meshes[0].material.type, Material::Type::Ggx);
  EXPECT_TRUE(s.meshes[0].albedoTexture);
  EXPECT_TRUE(s.meshes[0].material.albedo.isApprox(Eigen::Vector3f::Constant(0.5f)));
  // An albedo replaces both.
  s = scene(R"({"mesh": "m.obj", "material": {"type": "diffuse", "albedo": [0, 1, 0]}})");
  EXPECT_FALSE(s.meshes[0].albedoTexture);
  EXPECT_TRUE(s.meshes[0].material.albedo.isApprox(Eigen::Vector3f(0, 1, 0)));
  // A texture on a plane: white albedo unless given; on a sphere: refused.
  s = scene(R"({"shape": "plane", "center": [0, 0, 0], "normal": [0, 0, 1], "size": 1,
                "material": {"type": "diffuse", "texture": "red.png"}})");
  ASSERT_TRUE(s.meshes[0].albedoTexture);
  EXPECT_TRUE(s.meshes[0].material.albedo.isApprox(Eigen::Vector3f::Ones()));
  EXPECT_EQ(s.meshes[0].uvs.size(), 6u);
  EXPECT_THROW(scene(R"({"shape": "sphere", "center": [0, 0, 0], "radius": 1,
                         "material": {"type": "diffuse", "texture": "red.png"}})"),
               UserError);
  // A shape still needs a colour; a missing texture names itself.
  EXPECT_THROW(scene(R"({"shape": "plane", "center": [0, 0, 0], "normal": [0, 0, 1], "size": 1,
                         "material": {"type": "diffuse"}})"),
               UserError);
  try {
    scene(R"({"mesh": "m.obj", "material": {"type": "diffuse", "texture": "gone.png"}})");
    FAIL() << "a missing texture was accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("gone.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("objects[0].material.texture"), std::string::npos)
        << e.what();
  }
}

// Models nobody here made: Debian's assimp-testmodels (scripts/setup.sh).
const std::string kModels = "/usr/share/assimp/models/";

std::vector<TriangleMesh> loadRealModel(const std::string& relative) {
  const std::string path = kModels + relative;
  EXPECT_TRUE(std::filesystem::exists(path)) << path << ": run scripts/setup.sh";
  std::vector<std::string> warnings;
  const auto previous = setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
  std::vector<TriangleMesh> meshes;
  try {
    meshes = loadMeshFile(path);
  } catch (...) {
    setWarningHandler(previous);
    throw;
  }
  setWarningHandler(previous);
  for (const auto& w : warnings)  // the files' own flaws (zero normals) are not ours
    if (w.find("texture") != std::string::npos) ADD_FAILURE() << relative << ": " << w;
  return meshes;
}

TEST(ModelFiles, RealTexturedModelsLoadWithEveryTexture) {
  // The Collada duck: one material, its TGA texture, coordinates on every corner.
  const auto duck = loadRealModel("Collada/duck.dae");
  ASSERT_EQ(duck.size(), 1u);
  ASSERT_TRUE(duck[0].albedoTexture);
  EXPECT_EQ(duck[0].uvs.size(), 3 * duck[0].triangles.size());
  EXPECT_GT(duck[0].triangles.size(), 4000u);
  // The same glTF box with its image beside it and inside a GLB: the same texels.
  const auto external = loadRealModel("glTF2/BoxTextured-glTF/BoxTextured.gltf");
  const auto embedded = loadRealModel("glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");
  ASSERT_EQ(external.size(), 1u);
  ASSERT_EQ(embedded.size(), 1u);
  const auto& a = *external[0].albedoTexture;
  const auto& b = *embedded[0].albedoTexture;
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  for (int y = 0; y < a.height(); y += 17)
    for (int x = 0; x < a.width(); x += 13) ASSERT_TRUE(a.texel(x, y).isApprox(b.texel(x, y)));
  EXPECT_EQ(external[0].uvs, embedded[0].uvs);
  // An OBJ whose MTL names its JPEGs with Windows paths (.\SpiderTex.jpg).
  const auto spider = loadRealModel("OBJ/spider.obj");
  int textured = 0;
  for (const auto& m : spider) textured += m.albedoTexture != nullptr;
  EXPECT_GE(textured, 4);
}

}  // namespace
}  // namespace acpca
