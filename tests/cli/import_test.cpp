// `import` end to end: an OLAT set of 8-bit sRGB PNGs and a CSV of light
// directions made into a transport, described by `info`, relit, compressed,
// relit as a batch; and the mistakes of real captures refused.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "tests/cli/run_cli.h"
#include "tests/sphere_points.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;
constexpr int kWidth = 16, kHeight = 12, kLights = 24;

double srgbDecoded(int code) {
  const double c = code / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// A synthetic capture: pixel (x, y) is a Lambertian patch whose normal
/// turns across the image, of a colour of its own; pixel (0, 0) is black in
/// every image (background).
class ImportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream csv(dir_.file("lights.csv"));
    csv << "# a synthetic light stage\nimage,x,y,z\n";
    const auto lights = test::goldenSpiral(kLights);
    for (int k = 0; k < kLights; ++k) {
      std::vector<unsigned char> rgb(kWidth * kHeight * 3, 0);
      for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
          if (x == 0 && y == 0) continue;
          const Eigen::Vector3d n = Eigen::Vector3d(x - 7.5, y - 5.5, 8).normalized();
          const double shade = std::max(0.0, n.dot(lights[k]));
          for (int c = 0; c < 3; ++c)
            rgb[3 * (y * kWidth + x) + c] =
                static_cast<unsigned char>(std::lround(250 * shade * (0.4 + 0.2 * c)));
        }
      const std::string name = "olat_" + std::to_string(k) + ".png";
      write(dir_.file(name), rgb);
      images_.push_back(rgb);
      csv << name << "," << lights[k].x() << "," << lights[k].y() << "," << lights[k].z() << "\n";
    }
    lights_ = lights;
  }

  static void write(const std::string& path, const std::vector<unsigned char>& rgb) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, OIIO::ImageSpec(kWidth, kHeight, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) && out->close());
  }

  static std::vector<float> readExr(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    if (!in) return {};
    std::vector<float> v(static_cast<size_t>(in->spec().width) * in->spec().height * 3);
    in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, v.data());
    return v;
  }

  std::string f(const std::string& name) const { return dir_.file(name); }

  test::TempDir dir_;
  std::vector<std::vector<unsigned char>> images_;
  std::vector<Eigen::Vector3d> lights_;
};

TEST_F(ImportCli, ImportsDescribesAndRelightsACapturedSet) {
  const RunResult imported = runCli("import " + f("lights.csv") + " --out " + f("t.h5"));
  ASSERT_EQ(imported.status, 0) << imported.output;
  EXPECT_NE(imported.output.find("24 lights"), std::string::npos) << imported.output;

  const RunResult info = runCli("info " + f("t.h5"));
  ASSERT_EQ(info.status, 0) << info.output;
  EXPECT_NE(info.output.find("24 lights, spherical Voronoi cells capped at"), std::string::npos)
      << info.output;
  EXPECT_NE(info.output.find("uncovered"), std::string::npos) << info.output;
  const RunResult json = runCli("info " + f("t.h5") + " --json -");
  const auto j = nlohmann::json::parse(json.output);
  EXPECT_EQ(j["lights"]["count"], kLights);
  EXPECT_EQ(j["occupied_pixels"], kWidth * kHeight - 1);  // the black pixel left out
  EXPECT_EQ(j["row_layout"], "rgb");
  EXPECT_TRUE(j["camera"].is_null());

  // A 1-degree sun on light 5's direction gives back its image: the sun's
  // energy is its radiance times the disc's solid angle, the image was
  // taken under irradiance 1.
  const Eigen::Vector3d& d = lights_[5];
  const double theta = std::acos(d.y()) * 180 / kPi, phi = std::atan2(d.x(), -d.z()) * 180 / kPi;
  const double disc = 2 * kPi * (1 - std::cos(0.5 * kPi / 180));
  const RunResult sun = runCli("relight " + f("t.h5") + " --env sun:" + std::to_string(theta) +
                               "," + std::to_string(phi) + ",1," + std::to_string(1 / disc) +
                               " --exr-float --out " + f("sun.exr"));
  ASSERT_EQ(sun.status, 0) << sun.output;
  const std::vector<float> relit = readExr(f("sun.exr"));
  ASSERT_EQ(relit.size(), images_[5].size());
  for (size_t i = 0; i < relit.size(); ++i)
    ASSERT_NEAR(relit[i], srgbDecoded(images_[5][i]), 2e-3 * srgbDecoded(images_[5][i]) + 1e-6)
        << "value " << i;

  expectFailure("relight " + f("t.h5") + " --env sky --background env --out " + f("bg.exr"),
                "--background 'env': " + f("t.h5") + " is a captured light set");
  expectFailure(
      "relight " + f("t.h5") + " --env sky --fast-rotation --rotate 30 --out " + f("fast.exr"),
      "--fast-rotation");
  expectFailure("relight " + f("t.h5") + " --env sky --aov albedo --out " + f("albedo.exr"),
                "a captured light set holds images");
  EXPECT_FALSE(fs::exists(f("bg.exr")) || fs::exists(f("fast.exr")) || fs::exists(f("albedo.exr")));
}

TEST_F(ImportCli, ACompressedCaptureRelightsAsABatch) {
  ASSERT_EQ(runCli("import " + f("lights.csv") + " --quiet --out " + f("t.h5")).status, 0);
  const RunResult compressed =
      runCli("compress " + f("t.h5") + " --method adaptive-binary --quiet --out " + f("m.h5"));
  ASSERT_EQ(compressed.status, 0) << compressed.output;
  const RunResult info = runCli("info " + f("m.h5"));
  EXPECT_NE(info.output.find("24 lights"), std::string::npos) << info.output;
  const RunResult batch = runCli("relight " + f("m.h5") + " --env sky --env constant:1 --rotate " +
                                 "0:360:120 --quiet --out " + f("frames"));
  ASSERT_EQ(batch.status, 0) << batch.output;
  int frames = 0;
  for (const auto& e : fs::directory_iterator(f("frames")))
    frames += e.path().extension() == ".exr";
  EXPECT_EQ(frames, 6);
  // A light set has no camera: no camera files, and a COLMAP model is refused.
  EXPECT_FALSE(fs::exists(f("frames/transforms.json")));
  expectFailure(
      "relight " + f("m.h5") + " --env sky --rotate 0:360:120 --colmap --out " + f("colmap"),
      "--colmap '" + f("m.h5") + "': is a captured light set");
  EXPECT_FALSE(fs::exists(f("colmap")));
  // The batch benchmark takes the relight's default background, black.
  const RunResult bench = runCli("bench batch " + f("m.h5") + " --env sky --rotate 0:360:120 " +
                                 "--stream-gib 0.01 --quiet --out " + f("bench"));
  EXPECT_EQ(bench.status, 0) << bench.output;
  // The model against the transport under the same lighting.
  ASSERT_EQ(runCli("relight " + f("t.h5") + " --env sky --quiet --out " + f("dense.exr")).status,
            0);
  ASSERT_EQ(runCli("relight " + f("m.h5") + " --env sky --quiet --out " + f("model.exr")).status,
            0);
  const auto dense = readExr(f("dense.exr")), model = readExr(f("model.exr"));
  double num = 0, den = 0;
  for (size_t i = 0; i < dense.size(); ++i)
    num += std::pow(model[i] - dense[i], 2), den += double(dense[i]) * dense[i];
  EXPECT_LT(std::sqrt(num / den), 0.05);
}

TEST_F(ImportCli, RefusesTheMistakesOfRealCapturesAndWritesNothing) {
  const auto lightsWith = [&](const std::string& name, const std::string& extra) {
    std::ifstream in(f("lights.csv"));
    std::ofstream out(f(name));
    out << in.rdbuf() << extra;
  };
  lightsWith("missing.csv", "olat_missing.png,0.3,0.3,0.3\n");
  expectFailure("import " + f("missing.csv") + " --out " + f("x.h5"), "olat_missing.png");
  lightsWith("zero.csv", "olat_1.png,0,0,0\n");
  expectFailure("import " + f("zero.csv") + " --out " + f("x.h5"),
                f("zero.csv") + " line 27: the light's direction is zero");
  lightsWith("twice.csv", "olat_1.png," + std::to_string(lights_[3].x()) + "," +
                              std::to_string(lights_[3].y()) + "," +
                              std::to_string(lights_[3].z()) + "\n");
  expectFailure("import " + f("twice.csv") + " --out " + f("x.h5"), "the same direction as");
  // An image of another size.
  write(f("olat_0.png"), std::vector<unsigned char>(kWidth * kHeight * 3, 9));
  {
    auto out = OIIO::ImageOutput::create(f("small.png"));
    std::vector<unsigned char> v(8 * 8 * 3, 9);
    ASSERT_TRUE(out->open(f("small.png"), OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, v.data()) && out->close());
  }
  lightsWith("sizes.csv", "small.png,0.3,0.3,0.3\n");
  expectFailure("import " + f("sizes.csv") + " --out " + f("x.h5"), "small.png: 8x8, but");
  // A NaN in a float image.
  {
    std::vector<float> v(kWidth * kHeight * 3, 0.5f);
    v[7] = std::nanf("");
    auto out = OIIO::ImageOutput::create(f("nan.exr"));
    ASSERT_TRUE(
        out->open(f("nan.exr"), OIIO::ImageSpec(kWidth, kHeight, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, v.data()) && out->close());
  }
  lightsWith("nan.csv", "nan.exr,0.3,0.3,0.3\n");
  expectFailure("import " + f("nan.csv") + " --out " + f("x.h5"),
                "nan.exr: pixel (2, 0) is not a finite number");
  expectFailure("import " + f("lights.csv") + " --mask " + f("small.png") + " --out " + f("x.h5"),
                "the mask is 8x8");
  // Rows that cannot fit are refused before any image is read (ulimit -f
  // of 16 blocks: 8-16 KiB, the rows 27.6 KB).
  expectFailure("import " + f("lights.csv") + " --out " + f("x.h5"), "(ulimit -f)",
                "ulimit -f 16;");
  EXPECT_FALSE(fs::exists(f("x.h5")));
}

}  // namespace
}  // namespace acpca
