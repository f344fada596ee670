// Per-pixel labels against closed forms: a sphere's normal, planar depth,
// position and coverage from ray-sphere intersection, and a frame's shading
// times its albedo label giving the frame back.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dataset/batch_relight.h"
#include "dataset/pixel_labels.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "tests/temp_dir.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

/// Distance along the unit ray from `eye` to the unit sphere at the origin;
/// negative when it misses.
double hitDistance(const Vec3& eye, const Vec3& dir) {
  const double b = eye.dot(dir), c = eye.squaredNorm() - 1, disc = b * b - c;
  return disc < 0 ? -1 : -b - std::sqrt(disc);
}

const LabelLayer& layerOf(const std::vector<LabelLayer>& layers, Aov aov) {
  for (const LabelLayer& l : layers)
    if (l.aov == aov) return l;
  throw std::runtime_error("no such layer");
}

/// The built-in sphere's transport at `size`, written to `path`.
void precomputeSphere(const std::string& path, ImageSize size, const PrecomputeOptions& o) {
  Scene scene = makeBuiltinScene("sphere");
  scene.camera.size = size;
  precomputeTransport(scene, path, o);
}

TEST(PixelLabels, ASphereHasTheNormalDepthPositionAndCoverageOfItsClosedForm) {
  test::TempDir dir;
  PrecomputeOptions o;
  o.cubemapResolution = 4;
  o.samplesPerPixel = 8;
  o.antialiasing = Antialiasing::Full;  // every pixel takes all 8 samples
  precomputeSphere(dir.file("t.h5"), {24, 20}, o);
  const TransportReader t(dir.file("t.h5"));  // the labels come through the file
  const TransportHeader& h = t.header();
  ASSERT_EQ(h.objectNames, std::vector<std::string>{"sphere 0"});
  const std::vector<Aov> aovs = parseAovList("all");
  const std::vector<LabelLayer> layers = viewLabels(h, aovs);
  const auto& normal = layerOf(layers, Aov::Normal).values;
  const auto& depth = layerOf(layers, Aov::Depth).values;
  const auto& position = layerOf(layers, Aov::Position).values;
  const auto& mask = layerOf(layers, Aov::Mask).values;
  const auto& object = layerOf(layers, Aov::Object).values;
  const auto& albedo = layerOf(layers, Aov::Albedo).values;
  const Camera& cam = h.camera;
  int interior = 0, edge = 0;
  for (int y = 0; y < cam.size.height; ++y)
    for (int x = 0; x < cam.size.width; ++x) {
      const size_t p = static_cast<size_t>(y) * cam.size.width + x;
      int hits = 0;
      for (int s = 0; s < o.samplesPerPixel; ++s) {
        const Eigen::Vector2d at = Eigen::Vector2d(x, y) + pixelSampleOffset(s);
        hits += hitDistance(cam.eye, cam.rayDirection(at.x(), at.y())) > 0;
      }
      EXPECT_FLOAT_EQ(mask[p], float(hits) / o.samplesPerPixel) << x << "," << y;
      EXPECT_EQ(object[p], hits > 0 ? 0.0f : -1.0f);
      EXPECT_NEAR(albedo[3 * p], 0.5 * mask[p], 1e-6);
      if (hits == 0) {
        EXPECT_EQ(depth[p], 0.0f);
        continue;
      }
      edge += hits < o.samplesPerPixel;
      // The first sample is the pixel's centre: its hit is the one labelled.
      const Vec3 dir = cam.rayDirection(x + 0.5, y + 0.5);
      const double distance = hitDistance(cam.eye, dir);
      if (distance < 0) continue;  // an edge pixel whose centre misses
      ++interior;
      const Vec3 hit = cam.eye + distance * dir;
      const Vec3 n(normal[3 * p], normal[3 * p + 1], normal[3 * p + 2]);
      EXPECT_GT(n.dot(hit), 1 - 1e-4) << x << "," << y;
      EXPECT_NEAR(depth[p], distance * dir.dot(cam.forward()), 1e-4 * distance);
      const Vec3 labelled(position[3 * p], position[3 * p + 1], position[3 * p + 2]);
      EXPECT_LT((labelled - hit).norm(), 1e-4);
    }
  EXPECT_GT(interior, 100);
  EXPECT_GT(edge, 10);
}

/// An image file's pixels and channel names.
std::vector<float> readImage(const std::string& path, std::vector<std::string>* names = nullptr) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> pixels(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  in->read_image(0, 0, 0, -1, OIIO::TypeDesc::FLOAT, pixels.data());
  if (names) *names = spec.channelnames;
  return pixels;
}

TEST(PixelLabels, ShadingTimesAlbedoIsTheFrame) {
  test::TempDir dir;
  Scene scene = makePlantScene();
  scene.camera.size = {32, 32};
  PrecomputeOptions o;
  o.cubemapResolution = 8;
  o.precision = Precision::F32;
  precomputeTransport(scene, dir.file("t.h5"), o);
  for (Background background : {Background::Black, Background::Env, Background::Alpha}) {
    BatchRelightOptions a;
    a.input = dir.file("t.h5");
    a.envs = {"sky"};
    a.out = dir.file("frame.exr");
    a.background = background;
    a.exposure = 1.5;
    a.exrFloat = true;
    a.aovs = parseAovList("albedo,shading");
    relightBatch(a);
    std::vector<std::string> names;
    const std::vector<float> frame = readImage(dir.file("frame.exr"));
    const std::vector<float> shading = readImage(dir.file("frame_shading.exr"));
    const std::vector<float> labels = readImage(dir.file("frame_labels.exr"), &names);
    ASSERT_EQ(names, (std::vector<std::string>{"albedo.R", "albedo.G", "albedo.B"}));
    const int c = ImageComposer::channels(background);
    const size_t pixels = 32 * 32;
    ASSERT_EQ(frame.size(), pixels * c);
    ASSERT_EQ(shading.size(), pixels * 3);
    double worst = 0;
    int compared = 0;
    const TransportReader t(a.input);
    for (long long r = 0; r < t.rows(); ++r) {
      const size_t p = static_cast<size_t>(t.header().pixels[r]);
      // Where the background shows through (env), the frame is more than the object.
      if (background == Background::Env && t.header().coverage[r] < 1) continue;
      for (int k = 0; k < 3; ++k) {
        const double product = double(shading[3 * p + k]) * labels[3 * p + k];
        worst = std::max(worst, std::abs(product - frame[c * p + k]) /
                                    std::max(1e-6, double(std::abs(frame[c * p + k]))));
        ++compared;
      }
    }
    EXPECT_GT(compared, 300);
    EXPECT_LT(worst, 1e-5) << kBackgroundNames.name(background);
  }
}

TEST(PixelLabels, EachFramesLatticeLightingIsWrittenWithTheLatticesEnergy) {
  test::TempDir dir;
  PrecomputeOptions o;
  o.cubemapResolution = 8;
  precomputeSphere(dir.file("t.h5"), {8, 8}, o);
  BatchRelightOptions a;
  a.input = dir.file("t.h5");
  a.envs = {"constant:2", "sun:50,30,10,100"};
  a.out = dir.file("set");
  a.exposure = 3;  // the lighting is written before exposure
  a.exrFloat = true;
  a.lightingImages = true;
  relightBatch(a);
  const CubeLattice lattice(8);
  for (const char* name : {"00000_constant_2", "00001_sun_50_30_10_100"}) {
    const std::vector<float> image =
        readImage(dir.file(std::string("set/") + name + "_y0_lighting.exr"));
    ASSERT_EQ(image.size(), 64u * 32 * 3) << name;  // 8R x 4R
    // The integral over the sphere, pixel by pixel (lat-long solid angles),
    // against the lattice's own: sum of radiance x solid angle.
    const LatticeLighting lighting = computeLighting(
        *loadEnvironment(a.envs[name[4] == '0' ? 0 : 1]), lattice, {}, RotationMode::Exact);
    constexpr int kWidth = 64, kHeight = 32;
    double fromImage = 0;
    for (int y = 0; y < kHeight; ++y) {
      const double theta = (y + 0.5) * std::numbers::pi / kHeight;
      const double solidAngle =
          (2 * std::numbers::pi / kWidth) * (std::numbers::pi / kHeight) * std::sin(theta);
      for (int x = 0; x < kWidth; ++x) fromImage += image[3 * (y * kWidth + x)] * solidAngle;
    }
    // Equal up to the pixels' sampling of the texels (2.4% for this sun).
    EXPECT_NEAR(fromImage / totalEnergy(lighting).x(), 1, 0.05) << name;
    if (name[0] == 'c') {  // each pixel its texel's radiance
      for (float v : image) ASSERT_FLOAT_EQ(v, 2);
    }
  }
  const std::string manifest = test::readFile(dir.file("set/manifest.jsonl"));
  EXPECT_NE(manifest.find("\"lighting\":[\""), std::string::npos) << manifest;
}

}  // namespace
}  // namespace acpca
