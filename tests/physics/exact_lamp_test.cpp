// Point and spot lamps lit exactly (relight/lamp_light.h): closed forms over
// a floor, a shadow edge that falls once where the lattice drew stairs, an
// occluder beyond the lamp that no longer shadows it, against shadow rays
// rendered apart, and files that cannot be lit exactly falling back with a
// warning.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <numbers>

#include "cluster/compress.h"
#include "core/error.h"
#include "core/warning.h"
#include "model/model_file.h"
#include "precompute/scene.h"
#include "precompute/sphere_light_reference.h"
#include "precompute/transport_renderer.h"
#include "relight/local_relight.h"
#include "relight/relight_source.h"
#include "tests/render_support.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kAlbedo = 0.8f;

std::vector<float> lampRows(const std::string& path, const std::string& spec,
                            LampMode mode = LampMode::Exact) {
  const RelightSource source = openRelightSource(path);
  return source.relightLocal({parseLocalLight(spec)}, kAnchorSpreadTexels, mode);
}

Vec3 positionOf(const TransportHeader& h, long long r) {
  return {h.positions[3 * r], h.positions[3 * r + 1], h.positions[3 * r + 2]};
}

/// A diffuse floor from straight above, precomputed at `resolution`.
std::string floorTransport(const test::TempDir& dir, int resolution = 8) {
  const std::string path = dir.file(concat("floor", resolution, ".h5"));
  const Scene s = test::floorScene(24, {Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}});
  PrecomputeOptions o;
  o.cubemapResolution = resolution;
  precomputeTransport(s, path, o);
  return path;
}

TEST(ExactLamps, APointAndASpotOverAFloorAreTheClosedFormsToFloatPrecision) {
  const test::TempDir dir;
  const std::string path = floorTransport(dir);
  const TransportReader t(path);
  ASSERT_FALSE(t.header().lamps.empty());
  // Near, far outside the scene's bounds, and above the camera (behind it).
  for (const char* spec : {"point:0.2,1,0.1,3", "point:30,400,-20,3", "point:0,6,0,3"}) {
    const LocalLight light = parseLocalLight(spec);
    const std::vector<float> rgb = lampRows(path, spec);
    for (long long r = 0; r < t.rows(); ++r) {
      const Vec3 toLight = light.position - positionOf(t.header(), r);
      const double d = toLight.norm();
      const double expected = kAlbedo * 3 * (toLight.y() / d) / (kPi * d * d);
      ASSERT_NEAR(rgb[3 * r] / expected, 1, 1e-5) << spec << " row " << r;
    }
  }
  // A spot down the -Y axis, 20 degrees: as the point inside 18, dark past 20.
  const std::vector<float> spot = lampRows(path, "spot:0,1,0,0,-1,0,20,3");
  const std::vector<float> point = lampRows(path, "point:0,1,0,3");
  int inside = 0, outside = 0;
  for (long long r = 0; r < t.rows(); ++r) {
    const Vec3 toPixel = positionOf(t.header(), r) - Vec3(0, 1, 0);
    const double degrees = std::acos(-toPixel.normalized().y()) * 180 / kPi;
    if (degrees < 17.9) {
      EXPECT_FLOAT_EQ(spot[3 * r], point[3 * r]);
      ++inside;
    }
    if (degrees > 20.1) {
      EXPECT_EQ(spot[3 * r], 0.0f);
      ++outside;
    }
  }
  EXPECT_GT(inside, 10);
  EXPECT_GT(outside, 10);
}

TEST(ExactLamps, GlossyFloorsAgreeWithTheLatticeOfTheirTraces) {
  // Phong and GGX lobes broad enough for a 6x32x32 lattice: the exact lamp
  // (the BRDF at the lamp's direction, in double) against the rows the
  // precompute traced (its float lobe, per texel) lit through the lattice.
  Material phong{Material::Type::Phong, {kAlbedo, kAlbedo, kAlbedo}};
  phong.specular = 0.5, phong.exponent = 8;
  Material ggx{Material::Type::Ggx, {kAlbedo, kAlbedo, kAlbedo}};
  ggx.specular = 0.5, ggx.roughness = 0.5;
  for (const Material& material : {phong, ggx}) {
    const test::TempDir dir;
    Scene s = test::floorScene(24, material);
    s.camera.eye = {0, 3, 4};
    s.camera.up = {0, 1, 0};
    PrecomputeOptions o;
    o.cubemapResolution = 32;
    o.precision = Precision::F32;
    const std::string path = dir.file("t.h5");
    precomputeTransport(s, path, o);
    const char* spec = "point:0.3,1.2,-0.8,3";
    const auto exact = lampRows(path, spec), lattice = lampRows(path, spec, LampMode::Lattice);
    double err = 0, norm = 0;
    for (size_t i = 0; i < exact.size(); ++i)
      err += std::pow(double(exact[i]) - lattice[i], 2), norm += std::pow(double(lattice[i]), 2);
    EXPECT_LT(std::sqrt(err / norm), 0.01) << kMaterialTypeNames.name(material.type);
    RecordProperty(kMaterialTypeNames.name(material.type), std::to_string(std::sqrt(err / norm)));
  }
}

/// A floor from above with a wall just outside the view between it and a
/// lamp beyond: the wall's shadow edge runs across the image, so every
/// column crosses it once. The lit floor brightens toward the lamp, then
/// the shadow: one turn.
struct WallShadow {
  test::TempDir dir;
  std::string transport = dir.file("t.h5"), model = dir.file("m.h5");
  TransportHeader header;
  explicit WallShadow(int resolution) {
    Scene s = test::floorScene(32, {Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}});
    s.meshes.push_back(makeBox({-3, 0, 1.0}, {3, 0.6, 1.02},
                               {Material::Type::Diffuse, {0.5f, 0.5f, 0.5f}}, "wall"));
    PrecomputeOptions o;
    o.cubemapResolution = resolution;
    precomputeTransport(s, transport, o);
    const TransportReader t(transport);
    header = t.header();
    writeModel(compressTransport(t, CompressOptions{}), model);
  }
  static constexpr const char* kLamp = "point:0.1,1.2,1.5,4";
};

/// The most times a column of the image turns, counting only steps larger
/// than 2% of the brightest pixel.
int mostTurnsInAColumn(const TransportHeader& h, const std::vector<float>& rows) {
  const int w = h.camera.size.width, height = h.camera.size.height;
  std::vector<double> image(static_cast<size_t>(w) * height, 0);
  double brightest = 0;
  for (long long r = 0; r < h.rows(); ++r) {
    image[h.pixels[r]] = h.coverage[r] * rows[3 * r + 1];
    brightest = std::max(brightest, image[h.pixels[r]]);
  }
  int most = 0;
  for (int x = 0; x < w; ++x) {
    int turns = 0, last = 0;
    for (int y = 0; y + 1 < height; ++y) {
      const double step = image[(y + 1) * w + x] - image[y * w + x];
      if (std::abs(step) <= 0.02 * brightest) continue;
      const int sign = step > 0 ? 1 : -1;
      turns += last != 0 && sign != last;
      last = sign;
    }
    most = std::max(most, turns);
  }
  return most;
}

TEST(ExactLamps, AShadowEdgeTurnsOnceAlongEveryColumnFromTransportAndModel) {
  for (int resolution : {8, 32}) {
    const WallShadow scene(resolution);
    ASSERT_EQ(scene.header.rows(), 32 * 32);
    for (const std::string& path : {scene.transport, scene.model}) {
      const std::vector<float> exact = lampRows(path, WallShadow::kLamp);
      EXPECT_LE(mostTurnsInAColumn(scene.header, exact), 2) << path << " R = " << resolution;
      // Some floor is lit, some in shadow.
      const auto [darkest, brightest] = std::minmax_element(exact.begin(), exact.end());
      EXPECT_EQ(*darkest, 0.0f);
      EXPECT_GT(*brightest, 0.0f);
      RecordProperty(
          concat("lattice turns ", path == scene.model ? "model" : "transport", " R ", resolution),
          mostTurnsInAColumn(scene.header, lampRows(path, WallShadow::kLamp, LampMode::Lattice)));
    }
    // A lamp does not read T: the model lights it as the transport does,
    // and one thread as many.
    const std::vector<float> many = lampRows(scene.model, WallShadow::kLamp);
    EXPECT_EQ(many, lampRows(scene.transport, WallShadow::kLamp));
    tbb::task_arena one(1);
    EXPECT_EQ(one.execute([&] { return lampRows(scene.model, WallShadow::kLamp); }), many);
  }
}

TEST(ExactLamps, AnOccluderBeyondTheLampCastsNoShadowAndEdgesMatchShadowRays) {
  // A slab above a low lamp: the floor sees the lamp (the lattice's rows,
  // traced to infinity, did not). Against shadow rays to a sphere of tiny
  // radius rendered apart (precompute/sphere_light_reference.h).
  for (const bool slabAbove : {true, false}) {
    const test::TempDir dir;
    Scene s = test::floorScene(32, {Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}});
    if (slabAbove) {  // seen from the side, below the slab
      s.camera.eye = {2.5, 0.35, 0};
      s.camera.up = {0, 1, 0};
      s.camera.fovDegrees = 50;
    }
    if (slabAbove)
      s.meshes.push_back(makeBox({-4, 0.6, -4}, {4, 0.7, 4},
                                 {Material::Type::Diffuse, {0.5f, 0.5f, 0.5f}}, "slab"));
    else
      s.meshes.push_back(makeBox({-0.15, 0, -0.15}, {0.15, 0.2, 0.15},
                                 {Material::Type::Diffuse, {0.5f, 0.5f, 0.5f}}, "box"));
    PrecomputeOptions o;
    o.cubemapResolution = 8;
    o.samplesPerPixel = 1;
    const std::string path = dir.file("t.h5");
    precomputeTransport(s, path, o);
    const Vec3 lamp = slabAbove ? Vec3(0, 0.3, 0) : Vec3(0.3, 0.5, 0.2);
    const double radius = 1e-3, intensity = 0.5;
    const std::vector<float> exact =
        lampRows(path, concat("point:", lamp.x(), ",", lamp.y(), ",", lamp.z(), ",", intensity));
    // A sphere of radiance L shows as a point of intensity L pi r^2.
    const auto reference = renderSphereLightReference(
        s, {lamp, radius, Eigen::Vector3d::Constant(intensity / (kPi * radius * radius))}, 1, 64);
    ASSERT_EQ(exact.size(), reference.size());
    double err = 0, norm = 0;
    for (size_t i = 0; i < exact.size(); ++i)
      err += std::pow(double(exact[i]) - reference[i], 2),
          norm += std::pow(double(reference[i]), 2);
    EXPECT_GT(norm, 0);
    EXPECT_LT(std::sqrt(err / norm), 0.005) << (slabAbove ? "slab above" : "box below");
  }
}

TEST(ExactLamps, AFileWithoutSurfacesFallsBackToTheLatticeWithAWarning) {
  const test::TempDir dir;
  const std::string path = floorTransport(dir);
  const std::vector<float> lattice = lampRows(path, "point:0.2,1,0.1,3", LampMode::Lattice);
  {  // as a file of transport version 4, which had no lamp samples
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Ldelete(f, "lamp_sample_start", H5P_DEFAULT);
    H5Fclose(f);
  }
  std::vector<std::string> warnings;
  const WarningHandler previous =
      setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
  const RelightSource source = openRelightSource(path);
  const LocalLight lamp = parseLocalLight("point:0.2,1,0.1,3");
  EXPECT_EQ(source.relightLocal({lamp}, kAnchorSpreadTexels, LampMode::Exact), lattice);
  EXPECT_EQ(source.relightLocal({lamp}, kAnchorSpreadTexels, LampMode::Exact), lattice);
  setWarningHandler(previous);
  ASSERT_EQ(warnings.size(), 1u);  // once per file
  EXPECT_NE(warnings[0].find(path + ": lamps are lit through the lattice"), std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[0].find("precompute it again"), std::string::npos) << warnings[0];
}

TEST(ExactLamps, RowsWithBouncedLightKeepTheLatticeInTransportAndModel) {
  // The rows hold direct and bounced light summed, and a lamp's bounced part
  // is T's: both files say so and go through the lattice.
  const test::TempDir dir;
  const Scene s = test::floorScene(16, {Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}});
  PrecomputeOptions o;
  o.cubemapResolution = 4;
  o.bounces = 1;
  o.indirectSamples = 2;
  const std::string transport = dir.file("t.h5"), model = dir.file("m.h5");
  precomputeTransport(s, transport, o);
  writeModel(compressTransport(TransportReader(transport), CompressOptions{}), model);
  for (const std::string& path : {transport, model}) {
    const RelightSource source = openRelightSource(path);
    EXPECT_EQ(source.header.bounces, 1) << path;
    EXPECT_NE(exactLampsUnavailable(source.header, path == model).find("bounced light"),
              std::string::npos);
    std::vector<std::string> warnings;
    const WarningHandler previous =
        setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
    const LocalLight lamp = parseLocalLight("point:0.2,1,0.1,3");
    const auto rows = source.relightLocal({lamp}, kAnchorSpreadTexels, LampMode::Exact);
    setWarningHandler(previous);
    EXPECT_EQ(rows, source.relightLocal({lamp}, kAnchorSpreadTexels, LampMode::Lattice));
    EXPECT_EQ(warnings.size(), 1u) << path;
  }
}

}  // namespace
}  // namespace acpca
