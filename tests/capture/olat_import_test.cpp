// Importing one-light-at-a-time sets: exact sRGB decoding, calibration,
// coverage, refusals, and the round trip through the project's own relight
// (OLAT images made from a transport import to a transport that relights
// as the original did).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "capture/lights_file.h"
#include "capture/olat_import.h"
#include "core/error.h"
#include "imageio/image_output.h"
#include "lighting/domain_lighting.h"
#include "relight/dense_relight.h"
#include "relight/image_composer.h"
#include "tests/sphere_points.h"
#include "tests/temp_dir.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

/// The sRGB transfer function's inverse as IEC 61966-2-1 writes it.
double srgbDecoded(int code) {
  const double c = code / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

void writeImage(const std::string& path, int width, int height, int channels, OIIO::TypeDesc type,
                const void* values) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << path;
  ASSERT_TRUE(out->open(path, OIIO::ImageSpec(width, height, channels, type)));
  ASSERT_TRUE(out->write_image(type, values));
  ASSERT_TRUE(out->close());
}

OlatLights lightsAlong(std::vector<Vec3> directions) {
  OlatLights l;
  for (auto& d : directions) d.normalize();
  l.directions = directions;
  l.irradiance.assign(directions.size(), Eigen::Vector3d::Ones());
  return l;
}

std::vector<float> allRows(const std::string& path) {
  const TransportReader r(path);
  std::vector<float> rows(static_cast<size_t>(r.rows()) * r.rowLength());
  r.readRows(0, r.rows(), rows.data());
  return rows;
}

TEST(OlatImport, EightBitSrgbDecodesExactly) {
  test::TempDir dir;
  // One grey PNG of the codes 1, 10, 128, 254, 255 and a black pixel.
  const std::vector<unsigned char> codes{0, 1, 10, 128, 254, 255};
  const std::string png = dir.file("a.png");
  writeImage(png, 6, 1, 1, OIIO::TypeDesc::UINT8, codes.data());
  const auto images = openImageFiles({png}, TransferFunction::Auto);
  OlatImportOptions o;
  o.out = dir.file("t.h5");
  o.precision = Precision::F32;
  const OlatImportResult r = importOlat(*images, lightsAlong({{0, 1, 0}}), o);
  EXPECT_EQ(r.saturatedValues, 3);  // 255 in R, G and B
  EXPECT_EQ(r.header.channels, 1);  // grey
  const TransportReader t(o.out);
  EXPECT_EQ(t.header().pixels, (std::vector<std::int32_t>{1, 2, 3, 4, 5}));  // black left out
  const std::vector<float> rows = allRows(o.out);
  for (size_t i = 0; i < rows.size(); ++i)
    EXPECT_EQ(rows[i], static_cast<float>(srgbDecoded(codes[i + 1])))
        << "code " << int(codes[i + 1]);

  // --linear: the codes over 255.
  const auto linear = openImageFiles({png}, TransferFunction::Linear);
  o.out = dir.file("linear.h5");
  importOlat(*linear, lightsAlong({{0, 1, 0}}), o);
  const std::vector<float> lin = allRows(o.out);
  for (size_t i = 0; i < lin.size(); ++i) EXPECT_EQ(lin[i], codes[i + 1] / 255.0f);
}

TEST(OlatImport, AvifImagesAreReadAndSrgbDecoded) {
  // Public OLAT sets ship AVIF; Debian 12's OpenImageIO reads and writes it
  // through libheif (AV1). The codec is lossy and converts to YCbCr, so two
  // flat colours are checked to within a few codes of what was written.
  test::TempDir dir;
  if (!OIIO::ImageOutput::create(dir.file("probe.avif")))
    GTEST_SKIP() << "this OpenImageIO has no AVIF writer: " << OIIO::geterror();
  const int width = 32, height = 16;
  const std::vector<std::array<unsigned char, 3>> colours{{200, 120, 40}, {30, 90, 160}};
  std::vector<std::string> paths;
  for (size_t k = 0; k < colours.size(); ++k) {
    // OpenImageIO 2.4's HEIF writer reads up to a scanline past the image
    // (AddressSanitizer sees it): the buffer has four rows to spare.
    std::vector<unsigned char> pixels;
    for (int p = 0; p < width * (height + 4); ++p)
      pixels.insert(pixels.end(), colours[k].begin(), colours[k].end());
    paths.push_back(dir.file("olat_" + std::to_string(k) + ".avif"));
    writeImage(paths.back(), width, height, 3, OIIO::TypeDesc::UINT8, pixels.data());
  }
  const auto images = openImageFiles(paths, TransferFunction::Auto);
  OlatImportOptions o;
  o.out = dir.file("t.h5");
  o.precision = Precision::F32;
  const OlatImportResult r = importOlat(*images, lightsAlong({{0, 1, 0}, {1, 0, 0}}), o);
  ASSERT_EQ(r.header.channels, 3);
  ASSERT_EQ(r.header.pixels.size(), static_cast<size_t>(width * height));
  const std::vector<float> rows = allRows(o.out);
  // Row: R under each light, then G, then B.
  for (size_t p = 0; p < r.header.pixels.size(); ++p)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 2; ++k) {
        const int code = colours[k][c];
        EXPECT_GE(rows[p * 6 + c * 2 + k], srgbDecoded(code - 4)) << "pixel " << p;
        EXPECT_LE(rows[p * 6 + c * 2 + k], srgbDecoded(code + 4)) << "pixel " << p;
      }
}

TEST(OlatImport, RowsAreTheImagesOverTheirIrradianceColourByColour) {
  // Two lights, 2x1 pixels: light 0 red-ish, light 1 grey, E_1 = (2, 4, 8).
  const std::vector<float> values{0.5f, 0.25f, 0.125f, 0,    0,    0,      // image 0
                                  2.0f, 4.0f,  8.0f,   1.0f, 1.0f, 1.0f};  // image 1
  const auto images = imagesInMemory(values.data(), 2, {2, 1});
  OlatLights lights = lightsAlong({{0, 1, 0}, {1, 0, 0}});
  lights.irradiance[1] = {2, 4, 8};
  test::TempDir dir;
  OlatImportOptions o;
  o.out = dir.file("t.h5");
  o.precision = Precision::F32;
  const OlatImportResult r = importOlat(*images, lights, o);
  ASSERT_EQ(r.header.channels, 3);
  const std::vector<float> rows = allRows(o.out);
  // Row layout: the R value under each light, then G, then B.
  const std::vector<float> want{0.5f, 1.0f, 0.25f, 1.0f,  0.125f, 1.0f,
                                0.0f, 0.5f, 0.0f,  0.25f, 0.0f,   0.125f};
  EXPECT_EQ(rows, want);
  const TransportReader t(o.out);
  EXPECT_EQ(t.header().lights.irradiance[1], Eigen::Vector3d(2, 4, 8));
  EXPECT_EQ(t.header().albedo, std::vector<float>(6, 1.0f));
  EXPECT_EQ(t.header().lights.cells, CellSource::CappedVoronoi);
  EXPECT_DOUBLE_EQ(t.header().lights.capDegrees, 90);
}

TEST(OlatImport, AMaskIsTheCoverage) {
  test::TempDir dir;
  const std::vector<float> image(4 * 3, 0.5f);
  const std::vector<unsigned char> mask{0, 255, 51, 0};
  writeImage(dir.file("mask.png"), 4, 1, 1, OIIO::TypeDesc::UINT8, mask.data());
  const auto images = imagesInMemory(image.data(), 1, {4, 1});
  OlatImportOptions o;
  o.out = dir.file("t.h5");
  o.mask = dir.file("mask.png");
  importOlat(*images, lightsAlong({{0, 0, 1}}), o);
  const TransportReader t(o.out);
  EXPECT_EQ(t.header().pixels, (std::vector<std::int32_t>{1, 2}));
  ASSERT_EQ(t.header().coverage.size(), 2u);
  EXPECT_EQ(t.header().coverage[0], 1.0f);
  EXPECT_FLOAT_EQ(t.header().coverage[1], 51 / 255.0f);  // as stored, not sRGB-decoded
}

TEST(OlatImport, APartlyCoveredPixelRelightsToWhatItsImagesHold) {
  // Renderers store an edge pixel premultiplied by its coverage: an image
  // value of 0.1 at coverage 0.25 is a quarter of a surface at 0.4. The row
  // holds 0.4, and the relight on black, which multiplies by the coverage,
  // gives the image's 0.1 back.
  test::TempDir dir;
  const std::vector<float> image{0.8f, 0.6f, 0.4f, 0.1f, 0.2f, 0.3f};
  const std::vector<float> mask{1.0f, 0.25f};
  writeImage(dir.file("mask.exr"), 2, 1, 1, OIIO::TypeDesc::FLOAT, mask.data());
  const auto images = imagesInMemory(image.data(), 1, {2, 1});
  OlatImportOptions o;
  o.out = dir.file("t.h5");
  o.mask = dir.file("mask.exr");
  o.precision = Precision::F32;
  importOlat(*images, lightsAlong({{0, 1, 0}}), o);
  const std::vector<float> rows = allRows(o.out);
  ASSERT_EQ(rows.size(), 6u);
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(rows[3 + c], image[3 + c] / 0.25f);
  // Its light delivering irradiance 1 (a constant map of 1 / its cell), the
  // frame composed on black as `relight --background black` does.
  const TransportReader t(o.out);
  const double cell = t.header().lights.solidAngles[0];
  const DomainLighting domain(t.header());
  const auto relit =
      denseRelight(t, {domain(*makeConstantEnvironment(Rgb::Constant(1 / cell)), {})});
  std::vector<float> frame(6);
  const ImageComposer composer(t.header());
  composer.background(Background::Black, *makeConstantEnvironment(Rgb::Zero()),
                      Eigen::Matrix3d::Identity(), frame.data());
  composer.addRows(relit[0].data(), frame.data(), 3);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(frame[i], image[i], 1e-6) << "value " << i;
}

/// The message of the UserError `work` throws ("" if none).
template <typename Work>
std::string errorOf(Work work) {
  try {
    work();
  } catch (const UserError& e) {
    return e.what();
  }
  return "";
}

TEST(OlatImport, RefusesBadSetsAndWritesNothing) {
  test::TempDir dir;
  const std::vector<float> small(2 * 3, 0.5f), big(4 * 3, 0.5f);
  writeImage(dir.file("a.exr"), 2, 1, 3, OIIO::TypeDesc::FLOAT, small.data());
  writeImage(dir.file("b.exr"), 4, 1, 3, OIIO::TypeDesc::FLOAT, big.data());
  std::vector<float> withNan = small;
  withNan[4] = std::nanf("");
  writeImage(dir.file("nan.exr"), 2, 1, 3, OIIO::TypeDesc::FLOAT, withNan.data());
  EXPECT_NE(errorOf([&] {
              openImageFiles({dir.file("a.exr"), dir.file("b.exr")}, TransferFunction::Auto);
            }).find("b.exr: 4x1, but " + dir.file("a.exr") + " is 2x1"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              openImageFiles({dir.file("missing.png")}, TransferFunction::Auto);
            }).find("missing.png: cannot read the image"),
            std::string::npos);
  OlatImportOptions o;
  o.out = dir.file("t.h5");
  const auto nan = openImageFiles({dir.file("nan.exr")}, TransferFunction::Auto);
  EXPECT_NE(errorOf([&] {
              importOlat(*nan, lightsAlong({{0, 1, 0}}), o);
            }).find("nan.exr: pixel (1, 0) is not a finite number"),
            std::string::npos);
  const auto two = imagesInMemory(big.data(), 2, {2, 1});
  EXPECT_NE(errorOf([&] {
              importOlat(*two, lightsAlong({{0, 1, 0}}), o);
            }).find("2 images for 1 lights"),
            std::string::npos);
  const std::vector<float> black(2 * 3, 0.0f);
  const auto dark = imagesInMemory(black.data(), 1, {2, 1});
  EXPECT_NE(errorOf([&] {
              importOlat(*dark, lightsAlong({{0, 1, 0}}), o);
            }).find("every image is black"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(o.out));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 3);
}

/// A sun of 1 degree centred on d, of unit radiance.
std::unique_ptr<Environment> sunAt(const Vec3& d) {
  const double theta = std::acos(std::clamp(d.y(), -1.0, 1.0)) * 180 / kPi;
  const double phi = std::atan2(d.x(), -d.z()) * 180 / kPi;
  return makeSunEnvironment(theta, phi, 1.0, Rgb::Ones());
}

double relativeL2(const std::vector<float>& a, const std::vector<float>& b) {
  double num = 0, den = 0;
  for (size_t i = 0; i < a.size(); ++i) num += std::pow(a[i] - b[i], 2), den += double(b[i]) * b[i];
  return std::sqrt(num / den);
}

TEST(OlatImport, OlatImagesOfATransportRelightAsTheTransportDid) {
  // OLAT images of the small plant: light k a 1-degree sun at direction k.
  const TransportReader plant(test::fixture("small-plant"));
  const CubeLattice lattice(plant.header().cubemapResolution);
  const std::vector<Vec3> directions = test::goldenSpiral(600);
  std::vector<LatticeLighting> suns;
  for (const Vec3& d : directions) suns.push_back(computeLighting(*sunAt(d), lattice, {}));
  const std::vector<std::vector<float>> olat = denseRelight(plant, suns);
  const ImageSize size = plant.header().camera.size;
  const size_t perImage = static_cast<size_t>(size.pixels()) * 3;
  std::vector<float> images(directions.size() * perImage, 0.0f);
  for (size_t k = 0; k < directions.size(); ++k)
    for (long long r = 0; r < plant.rows(); ++r)
      for (int c = 0; c < 3; ++c)
        images[k * perImage + 3 * plant.header().pixels[r] + c] = olat[k][3 * r + c];
  OlatLights lights = lightsAlong(directions);
  for (size_t k = 0; k < directions.size(); ++k)
    lights.irradiance[k] = Eigen::Vector3d::Constant(totalEnergy(suns[k])[0]);
  test::TempDir dir;
  OlatImportOptions o;
  o.out = dir.file("olat.h5");
  o.precision = Precision::F32;
  auto source = imagesInMemory(images.data(), static_cast<int>(directions.size()), size);
  importOlat(*source, lights, o);
  const TransportReader imported(o.out);
  const DomainLighting cells(imported.header());

  // The imported rows are every pixel the plant lit; relight both the same.
  const auto onPlantPixels = [&](const std::vector<float>& rgb) {
    std::vector<float> image(perImage, 0.0f);
    for (long long r = 0; r < imported.rows(); ++r)
      for (int c = 0; c < 3; ++c) image[3 * imported.header().pixels[r] + c] = rgb[3 * r + c];
    std::vector<float> out;
    for (long long r = 0; r < plant.rows(); ++r)
      for (int c = 0; c < 3; ++c) out.push_back(image[3 * plant.header().pixels[r] + c]);
    return out;
  };
  // A sun inside one light's cell gives back that light's image exactly.
  for (int k : {0, 77, 599}) {
    const auto relit = denseRelight(imported, {cells(*sunAt(directions[k]), {})});
    const std::vector<float> mine = onPlantPixels(relit[0]);
    for (size_t i = 0; i < mine.size(); ++i)
      ASSERT_NEAR(mine[i], olat[k][i], 1e-6f * (1 + std::abs(olat[k][i]))) << "light " << k;
  }
  // Under a constant map the cells are a quadrature of the lattice's integral.
  const auto constant = makeConstantEnvironment(Rgb::Ones());
  const auto relit = denseRelight(imported, {cells(*constant, {})});
  const auto truth = denseRelight(plant, {computeLighting(*constant, lattice, {})});
  const double error = relativeL2(onPlantPixels(relit[0]), truth[0]);
  RecordProperty("constant_map_relative_l2", std::to_string(error));
  EXPECT_LT(error, 0.02);
}

}  // namespace
}  // namespace acpca
