// Textured albedo through the whole precompute, and anti-aliasing: a texture
// read from OBJ and glTF files comes back in the right place and colour, a
// checker's edge pixels hold the fractions the sample pattern predicts, and a
// texture edge on a shadow edge (the worst case for one albedo per pixel)
// matches a supersampled reference.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>

#include "lighting/lighting.h"
#include "precompute/scene.h"
#include "tests/render_support.h"
#include "tests/texture_support.h"

namespace acpca {
namespace {

using test::LoadedTransport;
using test::precomputeInMemory;

/// Relit RGB of every row (albedo applied) under one lattice lighting.
std::vector<Eigen::Vector3d> rgbRows(const LoadedTransport& t, const LatticeLighting& L) {
  std::vector<Eigen::Vector3d> out(t.header.rows());
  for (long long r = 0; r < t.header.rows(); ++r)
    for (int c = 0; c < 3; ++c) {
      double dot = 0;
      for (int j = 0; j < t.l; ++j) dot += double(t.row(r)[j]) * L[3 * j + c];
      out[r][c] = t.header.albedo[3 * r + c] * dot;
    }
  return out;
}

LatticeLighting lighting(const std::string& spec, int cubemap) {
  return computeLighting(*loadEnvironment(spec), CubeLattice(cubemap), {});
}

/// Where the ray through image point (px, py) meets the plane z = 0.
Vec3 onPlaneZ0(const Camera& camera, double px, double py) {
  const Vec3 d = camera.rayDirection(px, py);
  return camera.eye - camera.eye.z() / d.z() * d;
}

Camera frontCamera(int size) {
  Camera c;
  c.eye = {0, 0, 3};
  c.target = {0, 0, 0};
  c.up = {0, 1, 0};
  c.fovDegrees = 40;
  c.size = {size, size};
  return c;
}

// A 32x16 texture of 4x2 cells of 8x8 texels, every cell its own colour and
// no two mirror images alike: a flipped or swapped coordinate shows.
constexpr int kTexW = 32, kTexH = 16, kCell = 8;
Eigen::Vector3i cellCode(int i, int j) {  // column i from the left, row j from the top
  return {40 + 60 * i, 30 + 150 * j, 220 - 50 * i - 30 * j};
}

void writeLopsidedTexture(const std::string& path) {
  std::vector<unsigned char> texels;
  for (int y = 0; y < kTexH; ++y)
    for (int x = 0; x < kTexW; ++x)
      for (int c = 0; c < 3; ++c) texels.push_back(cellCode(x / kCell, y / kCell)[c]);
  test::writeImage8(path, kTexW, kTexH, 3, texels);
}

/// Checks that the quad x in [-1, 1], y in [-0.5, 0.5] at z = 0, textured
/// upright, relights under constant:1 to its texture times `factor` (1%).
void expectUprightTexture(const std::string& sceneFile, const Eigen::Vector3d& factor) {
  Scene scene = loadSceneJson(sceneFile);
  scene.camera = frontCamera(48);
  PrecomputeOptions o;
  o.cubemapResolution = 16;
  o.samplesPerPixel = 1;
  o.precision = Precision::F32;
  const LoadedTransport t = precomputeInMemory(scene, o);
  const auto relit = rgbRows(t, lighting("constant:1", 16));
  int checked = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const Vec3 p = onPlaneZ0(scene.camera, x + 0.5, y + 0.5);
      // Texel coordinates of the point, the image's top row at y = 0.5.
      const double tx = (p.x() + 1) / 2 * kTexW, ty = (0.5 - p.y()) * kTexH;
      const double inX = std::fmod(tx, kCell), inY = std::fmod(ty, kCell);
      if (tx < 0 || tx >= kTexW || ty < 0 || ty >= kTexH) continue;
      if (inX < 1 || inX > kCell - 1 || inY < 1 || inY > kCell - 1) continue;  // bilinear blend
      const long long r = test::rowOfPixel(t.header, x, y);
      ASSERT_GE(r, 0) << x << "," << y;
      const Eigen::Vector3i code = cellCode(int(tx) / kCell, int(ty) / kCell);
      for (int c = 0; c < 3; ++c) {
        const double expected = test::srgbCodeToLinear(code[c]) * factor[c];
        EXPECT_NEAR(relit[r][c], expected, 0.01 * expected)
            << sceneFile << " pixel " << x << "," << y << " channel " << c;
      }
      ++checked;
    }
  EXPECT_GT(checked, 200) << sceneFile;
}

TEST(Textures, ObjAndGltfQuadsRelightToTheirTextureUprightAndUnmirrored) {
  test::TempDir dir;
  writeLopsidedTexture(dir.file("lopsided.png"));
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.file(name), std::ios::binary) << text;
    return dir.file(name);
  };
  const std::string camera =
      R"("camera": {"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40})";
  // OBJ: v runs up, so the top edge has v = 1.
  write("quad.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd lopsided.png\n");
  write("quad.obj",
        "mtllib quad.mtl\nv -1 -0.5 0\nv 1 -0.5 0\nv 1 0.5 0\nv -1 0.5 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl tex\n"
        "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n");
  expectUprightTexture(write("obj.json", "{" + camera + R"(, "objects": [{"mesh": "quad.obj"}]})"),
                       {1, 1, 1});

  // glTF 2: v runs down (the top edge has v = 0), and baseColorFactor scales
  // the texture.
  std::string bin;
  const auto put = [&](const auto& values) {
    bin.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(values[0]));
  };
  put(std::vector<float>{-1, -0.5f, 0, 1, -0.5f, 0, 1, 0.5f, 0, -1, 0.5f, 0});
  put(std::vector<float>{0, 1, 1, 1, 1, 0, 0, 0});
  put(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3});
  write("quad.bin", bin);
  write("quad.gltf", R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                "indices": 2, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 1, 1],
                                            "baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}], "images": [{"uri": "lopsided.png"}],
    "buffers": [{"uri": "quad.bin", "byteLength": 92}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                    {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                   "min": [-1, -0.5, 0], "max": [1, 0.5, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]})");
  expectUprightTexture(
      write("gltf.json", "{" + camera + R"(, "objects": [{"mesh": "quad.gltf"}]})"), {1, 0.5, 1});
}

/// A texture of two halves along v (the bottom half `low`, the top `high`)
/// sharp to a thousandth of the quad.
std::shared_ptr<const Texture> halves(const Eigen::Vector3f& low, const Eigen::Vector3f& high) {
  constexpr int h = 1024;
  std::vector<float> rgb;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < 3; ++c) rgb.push_back(y < h / 2 ? high[c] : low[c]);
  return std::make_shared<const Texture>("halves", 2, h, std::move(rgb));
}

TEST(AntiAliasing, CheckerEdgePixelsHoldTheFractionsOfTheSamplePattern) {
  // A 2x2 checker of 256x256-texel cells (white top-left and bottom-right) on
  // a quad larger than the view, its edges off the pixel grid.
  constexpr int w = 512, size = 15, spp = 16;
  std::vector<float> rgb;
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) rgb.push_back((x < w / 2) == (y < w / 2) ? 1.0f : 0.0f);
  const Vec3 centre(0.013, -0.021, 0);
  Scene scene{"checker", frontCamera(size), {}, {}, {}, {}};
  scene.meshes.push_back(makeQuad(centre, {0, 0, 1}, 4, {}, "checker"));
  scene.meshes[0].material.albedo.setOnes();
  scene.meshes[0].albedoTexture = std::make_shared<const Texture>("checker", w, w, rgb);
  PrecomputeOptions o;
  o.cubemapResolution = 16;
  o.samplesPerPixel = spp;
  o.precision = Precision::F32;
  const LoadedTransport t = precomputeInMemory(scene, o);
  const auto relit = rgbRows(t, lighting("constant:1", 16));
  // Bilinear lookup turns each step into a one-texel ramp: the share of white
  // along one axis, as a function of the texel coordinate f (centres at i + 0.5).
  const auto ramp = [&](double f) { return std::clamp(f - 0.5 - (w / 2 - 1), 0.0, 1.0); };
  int edges = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      double predicted = 0;
      for (int s = 0; s < spp; ++s) {
        const Eigen::Vector2d o = pixelSampleOffset(s);
        const Vec3 p = onPlaneZ0(scene.camera, x + o.x(), y + o.y()) - centre;
        // makeQuad facing +Z: u along +X, v along +Y; image rows run down.
        const double right = ramp((p.x() + 2) / 4 * w), lower = ramp((2 - p.y()) / 4 * w);
        predicted += (right * lower + (1 - right) * (1 - lower)) / spp;
      }
      const long long r = test::rowOfPixel(t.header, x, y);
      ASSERT_GE(r, 0);
      EXPECT_NEAR(t.header.albedo[3 * r], predicted, 1e-4) << x << "," << y;
      EXPECT_NEAR(relit[r].x(), predicted, 0.01) << x << "," << y;
      edges += predicted > 0.01 && predicted < 0.99;
    }
  EXPECT_GE(edges, 2 * size - 4);  // a row and a column of pixels straddle the edges
}

/// The worst case for one albedo per pixel: a floor whose texture changes
/// exactly where a wall's shadow begins. The wall stands on the edge in a plane
/// through the eye (so it is seen edge-on, not at all); a low sun from +X
/// lights the +X side and the wall shades the rest.
Scene wallOnTextureEdge(int size, const Eigen::Vector3f& shaded, const Eigen::Vector3f& lit) {
  constexpr double edge = 0.017;
  Scene scene{"wall", {}, {}, {}, {}, {}};
  // Looking straight down at the edge: it halves the middle column of an odd
  // image, on the boundary of the reference's finer pixels too.
  scene.camera.eye = {edge, 3, 0};
  scene.camera.target = {edge, 0, 0};
  scene.camera.up = {0, 0, -1};
  scene.camera.fovDegrees = 30;
  scene.camera.size = {size, size};
  // The floor facing +Y has v along +X: the bottom half of the texture (low v)
  // is the -X side.
  TriangleMesh floor = makeQuad({edge, 0, 0}, {0, 1, 0}, 4, {}, "floor");
  floor.material.albedo.setOnes();
  floor.albedoTexture = halves(shaded, lit);
  scene.meshes.push_back(std::move(floor));
  scene.meshes.push_back(makeQuad({edge, 1, 0}, {1, 0, 0}, 2, {}, "wall"));
  return scene;
}

/// Relit pixels, the scene's transport under a sun from +X at 30 degrees of
/// elevation plus a dim constant sky.
std::vector<Eigen::Vector3d> relitImage(const Scene& scene, const PrecomputeOptions& o) {
  const LoadedTransport t = precomputeInMemory(scene, o);
  LatticeLighting L = lighting("sun:60,90,4,1000", o.cubemapResolution);
  const LatticeLighting sky = lighting("constant:0.1", o.cubemapResolution);
  for (size_t i = 0; i < L.size(); ++i) L[i] += sky[i];
  const auto rows = rgbRows(t, L);
  std::vector<Eigen::Vector3d> image(scene.camera.size.pixels(), Eigen::Vector3d::Zero());
  for (long long r = 0; r < t.header.rows(); ++r)
    image[t.header.pixels[r]] = t.header.coverage[r] * rows[r];
  return image;
}

/// Largest difference (per channel, and of luminance) between the scene at
/// `size` with `spp` samples and the 8x8 box average of it at 8 times the size.
struct EdgeErrors {
  double channel = 0, luminance = 0, brightest = 0;
};
EdgeErrors againstSupersampled(const Eigen::Vector3f& shaded, const Eigen::Vector3f& lit,
                               Antialiasing mode) {
  constexpr int size = 15, factor = 8;
  PrecomputeOptions o;
  o.cubemapResolution = 16;
  o.precision = Precision::F32;
  o.samplesPerPixel = 1;
  const auto fine = relitImage(wallOnTextureEdge(size * factor, shaded, lit), o);
  o.samplesPerPixel = 64;
  o.antialiasing = mode;
  const auto coarse = relitImage(wallOnTextureEdge(size, shaded, lit), o);
  const Eigen::Vector3d y709(0.2126, 0.7152, 0.0722);
  EdgeErrors e;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      Eigen::Vector3d reference = Eigen::Vector3d::Zero();
      for (int v = 0; v < factor; ++v)
        for (int u = 0; u < factor; ++u)
          reference += fine[(y * factor + v) * size * factor + x * factor + u];
      reference /= factor * factor;
      const Eigen::Vector3d d = coarse[y * size + x] - reference;
      e.channel = std::max(e.channel, d.cwiseAbs().maxCoeff());
      e.luminance = std::max(e.luminance, std::abs(d.dot(y709)));
      e.brightest = std::max(e.brightest, reference.maxCoeff());
    }
  return e;
}

TEST(AntiAliasing, ATextureEdgeOnAShadowEdgeMatchesASupersampledReference) {
  // Black in the shade, white in the sun: one hue, so albedo x luminance-
  // weighted row is exact; only the sample pattern differs from the reference.
  const EdgeErrors grey = againstSupersampled({0, 0, 0}, {1, 1, 1}, Antialiasing::Full);
  ASSERT_GT(grey.brightest, 0.3);
  EXPECT_LT(grey.channel, 0.02 * grey.brightest);
  // Green in the shade, red in the sun: luminance stays exact; the hue of
  // the edge pixels is what one albedo per pixel cannot hold (docs/scenes.md).
  const EdgeErrors hue = againstSupersampled({0, 1, 0}, {1, 0, 0}, Antialiasing::Full);
  EXPECT_LT(hue.luminance, 0.03 * hue.brightest);
  RecordProperty("grey_edge_error", std::to_string(grey.channel / grey.brightest));
  RecordProperty("hue_edge_channel_error", std::to_string(hue.channel / hue.brightest));
  RecordProperty("hue_edge_luminance_error", std::to_string(hue.luminance / hue.brightest));
  // Adaptive traces the floor's pixels at their centre alone: the shadow edge
  // inside them is point-sampled, as documented, while the texture is not.
  const EdgeErrors adaptive = againstSupersampled({0, 0, 0}, {1, 1, 1}, Antialiasing::Adaptive);
  RecordProperty("adaptive_edge_error", std::to_string(adaptive.channel / adaptive.brightest));
  std::printf(
      "edge errors / brightest: full grey %.4f, full hue %.4f (luminance %.4f), "
      "adaptive grey %.4f\n",
      grey.channel / grey.brightest, hue.channel / hue.brightest, hue.luminance / hue.brightest,
      adaptive.channel / adaptive.brightest);
}

}  // namespace
}  // namespace acpca
