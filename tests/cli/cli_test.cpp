// End-to-end runs of the real `adaptive-cpca` binary on tiny inputs: the happy
// path, and bad input giving a clear message, a non-zero exit and no partial file.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "model/model_file.h"
#include "tests/cli/image_pixels.h"
#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;

size_t filesIn(const test::fs::path& dir) {
  size_t n = 0;
  for (const auto& e : test::fs::recursive_directory_iterator(dir)) n += e.is_regular_file();
  return n;
}

class Cli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    transport_ = dir_->file("sphere.h5");
    const RunResult r =
        runCli("precompute --scene sphere --size 20x16 --cubemap 8 --quiet --out " + transport_);
    ASSERT_EQ(r.status, 0) << r.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static TempDir* dir_;
  static std::string transport_;
};
TempDir* Cli::dir_ = nullptr;
std::string Cli::transport_;

TEST_F(Cli, PrecomputeInfoAndRelightWork) {
  const RunResult info = runCli("info " + transport_ + " --json -");
  ASSERT_EQ(info.status, 0) << info.output;
  const auto j = nlohmann::json::parse(info.output);
  EXPECT_EQ(j["kind"], "transport");
  EXPECT_EQ(j["width"], 20);
  EXPECT_EQ(j["cubemap"], 8);
  EXPECT_GT(j["occupied_pixels"].get<int>(), 50);

  TempDir out;
  const RunResult one =
      runCli("relight " + transport_ + " --env constant:1 --quiet --format both --out " +
             out.file("furnace.exr"));
  ASSERT_EQ(one.status, 0) << one.output;
  EXPECT_TRUE(test::fs::exists(out.file("furnace.exr")));
  EXPECT_TRUE(test::fs::exists(out.file("furnace.png")));
  // The furnace, read back from the EXR: the sphere is 0.5 and the sky is 1.
  auto in = OIIO::ImageInput::open(out.file("furnace.exr"));
  ASSERT_TRUE(in);
  std::vector<float> px(20 * 16 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data()));
  EXPECT_NEAR(px[3 * (8 * 20 + 10)], 0.5, 0.005);
  EXPECT_NEAR(px[0], 1.0, 1e-3);

  const RunResult batch =
      runCli("relight " + transport_ +
             " --env sky --env sun:50,30,4,1000 --rotate 0:90:45 --quiet --json " +
             out.file("r.json") + " --out " + out.file("batch"));
  ASSERT_EQ(batch.status, 0) << batch.output;
  for (const char* name : {"00000_sky_y0.exr", "00001_sky_y45.exr", "00002_sun_50_30_4_1000_y0.exr",
                           "00003_sun_50_30_4_1000_y45.exr", "manifest.csv"})
    EXPECT_TRUE(test::fs::exists(out.path() / "batch" / name)) << name;
  const auto report = nlohmann::json::parse(std::ifstream(out.file("r.json")));
  EXPECT_EQ(report["frames"], 4);
  EXPECT_GT(report["ms_per_frame_median"].get<double>(), 0);

  const RunResult envmap = runCli("envmap sky --cubemap 8 --size 64x32 --quiet --out " +
                                  out.file("sky.exr") + " --cross " + out.file("cross.exr"));
  ASSERT_EQ(envmap.status, 0) << envmap.output;
  EXPECT_TRUE(test::fs::exists(out.file("cross.exr")));
  EXPECT_EQ(runCli("scenes").status, 0);

  // manifest.jsonl names a lighting file by its bytes' SHA-256 (as coreutils'
  // sha256sum prints it), a built-in one by its spec alone.
  const RunResult files = runCli("relight " + transport_ + " --env " + out.file("sky.exr") +
                                 " --env sky --quiet --out " + out.file("files"));
  ASSERT_EQ(files.status, 0) << files.output;
  const RunResult sum = runShell("sha256sum " + out.file("sky.exr"));
  ASSERT_EQ(sum.status, 0) << sum.output;
  std::ifstream lines(out.file("files/manifest.jsonl"));
  std::string first, second;
  ASSERT_TRUE(std::getline(lines, first) && std::getline(lines, second));
  EXPECT_EQ(nlohmann::json::parse(first)["env_sha256"], sum.output.substr(0, 64));
  EXPECT_TRUE(nlohmann::json::parse(second)["env_sha256"].is_null()) << second;

  // Every format of one frame holds its values: float EXR and .npy alike,
  // the 16-bit PNG their sRGB codes (ACES-mapped under --tone aces).
  const RunResult formats = runCli("relight " + transport_ +
                                   " --env sky --rotate 0:90:45 --exposure 1 --exr-float --format "
                                   "exr,npy,png16 --tone aces --quiet --out " +
                                   out.file("formats"));
  ASSERT_EQ(formats.status, 0) << formats.output;
  auto exr = OIIO::ImageInput::open(out.file("formats/00001_sky_y45.exr"));
  auto png = OIIO::ImageInput::open(out.file("formats/00001_sky_y45.png"));
  ASSERT_TRUE(exr && png);
  std::vector<float> linear(20 * 16 * 3);
  std::vector<std::uint16_t> codes(linear.size());
  ASSERT_TRUE(exr->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, linear.data()));
  ASSERT_TRUE(png->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT16, codes.data()));
  std::ifstream npyFile(out.file("formats/00001_sky_y45.npy"), std::ios::binary);
  const std::string npy((std::istreambuf_iterator<char>(npyFile)),
                        std::istreambuf_iterator<char>());
  ASSERT_GE(npy.size(), linear.size() * 4);
  std::vector<float> fromNpy(linear.size());
  std::memcpy(fromNpy.data(), npy.data() + npy.size() - linear.size() * 4, linear.size() * 4);
  EXPECT_EQ(fromNpy, linear);
  for (size_t i = 0; i < linear.size(); ++i) {
    const double v = linear[i];  // exposure applied
    const double aces =
        std::clamp(v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14), 0.0, 1.0);
    const double srgb = aces <= 0.0031308 ? 12.92 * aces : 1.055 * std::pow(aces, 1 / 2.4) - 0.055;
    ASSERT_NEAR(codes[i], 65535 * srgb, 0.51) << i;
  }
}

TEST_F(Cli, ParameterErrorsNameTheFlagThatSetsThem) {
  // Flags named after their parameter (--global-energy) and those that are
  // not (--spp: "samples per pixel"), over the commands that share them.
  TempDir out;
  const std::string t = " --out " + out.file("t.h5");
  const std::string image = " --out " + out.file("r.exr");
  for (const auto& [args, flag] : std::vector<std::pair<std::string, std::string>>{
           {"precompute --scene sphere --spp 0" + t, "--spp '0'"},
           {"build --scene sphere --texel-rays 0" + t, "--texel-rays '0'"},
           {"compress " + transport_ + " --method adaptive-quad --global-energy 2" + t,
            "--global-energy '2'"},
           {"compress " + transport_ + " --method block --block -4" + t, "--block '-4'"},
           {"relight " + transport_ + " --env sky --rotate 0:0:5" + image, "--rotate '0:0:5'"},
           {"relight " + transport_ + " --env sun:1,2" + image, "--env 'sun:1,2'"},
           {"relight " + transport_ + " --env sky --aov albedo,diffuse" + image, "--aov 'diffuse'"},
           {"relight " + transport_ + " --env sky --aov all --label-format tiff" + image,
            "--label-format 'tiff'"},
           {"relight " + transport_ + " --env sky --format png,png16" + image,
            "--format 'png,png16'"},
           {"relight " + transport_ + " --env sky --tone reinhard" + image, "--tone 'reinhard'"},
           {"relight " + transport_ + " --env sky --env-sample 0" + image, "--env-sample '0'"},
           {"relight " + transport_ + " --env sky --env-sample 2 --seed x" + image, "--seed"},
           {"bench relight " + transport_ + " --frames 0", "--frames '0'"}}) {
    expectFailure(args, flag);
  }
  EXPECT_EQ(filesIn(out.path()), 0u);
}

TEST_F(Cli, BadInputIsAClearErrorWithNothingHalfWritten) {
  TempDir out;
  expectFailure("precompute --scene teapot --out " + out.file("t.h5"), "teapot");
  expectFailure("precompute --scene sphere --size 0x10 --out " + out.file("t.h5"), "0x10");
  expectFailure("precompute --scene sphere --size 100000x100000 --out " + out.file("t.h5"),
                "out of range");
  expectFailure("precompute --scene sphere --cubemap 0 --out " + out.file("t.h5"), "cubemap");
  expectFailure("precompute --scene sphere --bounces 99 --out " + out.file("t.h5"),
                "--bounces '99'");
  expectFailure(
      "precompute --scene sphere --bounces 1 --indirect-samples 0 --out " + out.file("t.h5"),
      "--indirect-samples '0'");
  expectFailure(
      "precompute --scene sphere --bounces 1 --indirect-cache 2 --out " + out.file("t.h5"),
      "--indirect-cache '2'");
  expectFailure("precompute --scene sphere --size 8x8 --out /nonexistent-dir/t.h5",
                "nonexistent-dir");
  {
    std::ofstream(out.file("bad.json")) << R"({"camera": {"eye": [0,0,5], "target": [0,0,0],
      "up": [0,1,0], "fov": 40}, "objects": [{"shape": "sphere", "centre": [0,0,0], "radius": 1,
      "material": {"type": "diffuse", "albedo": [1,1,1]}}]})";
  }
  expectFailure("precompute --scene " + out.file("bad.json") + " --out " + out.file("t.h5"),
                "'centre'");
  expectFailure("relight " + out.file("missing.h5") + " --env sky --out " + out.file("x.exr"),
                "missing.h5");
  { std::ofstream(out.file("junk.h5")) << "junk"; }
  expectFailure("relight " + out.file("junk.h5") + " --env sky --out " + out.file("x.exr"),
                "junk.h5");
  expectFailure("relight " + transport_ + " --env sun:1,2 --out " + out.file("x.exr"), "sun:1,2");
  expectFailure("relight " + transport_ + " --env sky --rotate 1,2 --out " + out.file("x.exr"),
                "1,2");
  expectFailure("relight " + transport_ + " --env sky --out " + out.file("x.bmpx"), "format");
  expectFailure("relight " + transport_ + " --env sky --out /nonexistent-dir/x.exr",
                "nonexistent-dir");
  {  // An env map with a NaN texel.
    std::vector<float> pixels(3 * 8 * 4, 1.0f);
    pixels[5] = NAN;
    auto o = OIIO::ImageOutput::create(out.file("nan.exr"));
    o->open(out.file("nan.exr"), OIIO::ImageSpec(8, 4, 3, OIIO::TypeDesc::FLOAT));
    o->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
    o->close();
  }
  expectFailure(
      "relight " + transport_ + " --env " + out.file("nan.exr") + " --out " + out.file("x.exr"),
      "nan.exr");
  // Only the inputs the test wrote itself are left: no outputs, no temporaries.
  EXPECT_EQ(filesIn(out.path()), 3u);

  // In a batch the good maps are still done and the bad one is listed.
  const RunResult r = runCli("relight " + transport_ + " --env sky --env " + out.file("nan.exr") +
                             " --env constant:1 --quiet --out " + out.file("batch"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("nan.exr"), std::string::npos) << r.output;
  EXPECT_TRUE(test::fs::exists(out.path() / "batch" / "00000_sky_y0.exr"));
  EXPECT_TRUE(test::fs::exists(out.path() / "batch" / "00001_constant_1_y0.exr"));
  EXPECT_TRUE(test::fs::exists(out.path() / "batch" / "manifest.csv"));
}

TEST_F(Cli, MapsLoadedTogetherWarnAndFailInTheOrderGiven) {
  TempDir out;
  // Maps read at once: each one's warning (negative texels clamped) or
  // failure (a NaN) comes in the order the maps were given.
  const auto mapPath = [&](int k) {
    std::string name = "m";  // appended, not "m" + ...: GCC 12's -Wrestrict misfires there
    name += std::to_string(k);
    name += ".exr";
    return out.file(name);
  };
  std::string envs;
  for (int k = 0; k < 6; ++k) {
    std::vector<float> pixels(3 * 64 * 32, 1.0f);
    const std::string name = mapPath(k);
    pixels[7] = k % 3 == 1 ? NAN : -0.05f * (k + 1);
    auto o = OIIO::ImageOutput::create(name);
    o->open(name, OIIO::ImageSpec(64, 32, 3, OIIO::TypeDesc::FLOAT));
    o->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
    o->close();
    envs += " --env " + name;
  }
  const RunResult r = runCli("relight " + transport_ + envs + " --out " + out.file("b"));
  EXPECT_NE(r.status, 0);  // two maps could not be used
  size_t from = 0;
  for (int k = 0; k < 6; ++k) {
    std::string said = mapPath(k);
    said.append(k % 3 == 1 ? ": pixel (2, 0) channel 1" : ": 1 negative values clamped");
    const size_t at = r.output.find(said, from);
    ASSERT_NE(at, std::string::npos) << said << " after " << from << " in\n" << r.output;
    from = at;
  }
  EXPECT_TRUE(test::fs::exists(out.path() / "b" / "00000_m0_y0.exr"));
  EXPECT_TRUE(test::fs::exists(out.path() / "b" / "00003_m5_y0.exr"));
  // A model that cannot be read is named first, though its maps load beside it.
  expectFailure("relight " + out.file("missing.h5") + envs + " --out " + out.file("c"),
                "missing.h5");
}

TEST_F(Cli, CompressInfoAndRelightAModel) {
  TempDir out;
  const RunResult c = runCli("compress " + transport_ + " --method adaptive-quad --quiet --out " +
                             out.file("m.h5") + " --json " + out.file("c.json"));
  ASSERT_EQ(c.status, 0) << c.output;
  const auto report = nlohmann::json::parse(std::ifstream(out.file("c.json")));
  EXPECT_GT(report["cost_per_pixel"].get<double>(), 0);
  EXPECT_LT(report["transport_error"].get<double>(), 0.1);
  const RunResult info = runCli("info " + out.file("m.h5") + " --json -");
  ASSERT_EQ(info.status, 0) << info.output;
  const auto j = nlohmann::json::parse(info.output);
  EXPECT_EQ(j["kind"], "model");
  EXPECT_EQ(j["method"], "adaptive-quad");
  EXPECT_GE(j["clusters"].get<int>(), 1);
  const RunResult r =
      runCli("relight " + out.file("m.h5") + " --env sky --quiet --out " + out.file("m.png"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(test::fs::exists(out.file("m.png")));
  // The same inputs give the same bytes, EXR included (no time stamp).
  for (const char* name : {"a.exr", "b.exr"})
    ASSERT_EQ(
        runCli("relight " + out.file("m.h5") + " --env sky --quiet --out " + out.file(name)).status,
        0);
  const auto bytes = [](const std::string& path) {
    std::ostringstream s;
    s << std::ifstream(path, std::ios::binary).rdbuf();
    return s.str();
  };
  EXPECT_GT(bytes(out.file("a.exr")).size(), 100u);
  EXPECT_EQ(bytes(out.file("a.exr")), bytes(out.file("b.exr")));
  auto exr = OIIO::ImageInput::open(out.file("a.exr"));
  ASSERT_TRUE(exr);
  EXPECT_EQ(exr->spec().find_attribute("DateTime"), nullptr);
  expectFailure("compress " + transport_ + " --method kmeans --out " + out.file("x.h5"), "kmeans");
  expectFailure("compress " + transport_ + " --method cpca --tolerance 2 --out " + out.file("x.h5"),
                "--tolerance");
  expectFailure("compress " + transport_ + " --method adaptive-binary --clustering-dims -1 --out " +
                    out.file("x.h5"),
                "--clustering-dims '-1'");
  expectFailure("compress " + out.file("m.h5") + " --method global --out " + out.file("x.h5"),
                "not an adaptive-cpca transport");
  EXPECT_FALSE(test::fs::exists(out.file("x.h5")));
}

/// The pixels of an image file as floats (empty if it cannot be read).
double maxDifference(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size() || a.empty()) return INFINITY;
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(double(a[i]) - b[i]));
  return d;
}

TEST_F(Cli, LocalLightsLightAloneAddToEnvironmentsAndListInTheManifest) {
  TempDir out;
  // The sphere scene: a unit sphere at the origin, seen from +Z.
  const std::string lamp = "--light point:1.5,2.5,2,30 --light sphere:-2,1,1.5,0.3,60,50,40";
  const std::string relight = "relight " + transport_ + " --quiet --exr-float ";
  ASSERT_EQ(runCli(relight + lamp + " --out " + out.file("lamp.exr")).status, 0);
  ASSERT_EQ(runCli(relight + "--env sky --out " + out.file("sky.exr")).status, 0);
  const RunResult both = runCli(relight + lamp + " --env sky --out " + out.file("both.exr"));
  ASSERT_EQ(both.status, 0) << both.output;
  const auto alone = test::readPixels(out.file("lamp.exr")),
             sky = test::readPixels(out.file("sky.exr")),
             sum = test::readPixels(out.file("both.exr"));
  ASSERT_FALSE(alone.empty());
  double peak = 0, lit = 0;
  for (size_t i = 0; i < alone.size(); ++i) {
    peak = std::max(peak, double(sum[i]));
    lit += alone[i];
    EXPECT_NEAR(sum[i], alone[i] + sky[i], 1e-6 * (alone[i] + sky[i]) + 1e-7) << i;
  }
  EXPECT_GT(lit, 0) << "the lamps light something";

  // A batch lists the lights of its frames.
  ASSERT_EQ(
      runCli(relight + lamp + " --env sky --env constant:1 --out " + out.file("batch")).status, 0);
  const std::string manifest = test::readFile(out.file("batch/manifest.csv"));
  EXPECT_NE(manifest.find("exposure,lights,output"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"point:1.5,2.5,2,30;sphere:-2,1,1.5,0.3,60,50,40\""), std::string::npos)
      << manifest;

  // A model relights the lamps too, within its compression error.
  const std::string model = out.file("m.h5");
  ASSERT_EQ(
      runCli("compress " + transport_ + " --method adaptive-quad --quiet --out " + model).status,
      0);
  ASSERT_EQ(runCli("relight " + model + " --quiet --exr-float " + lamp + " --out " +
                   out.file("model.exr"))
                .status,
            0);
  const auto fromModel = test::readPixels(out.file("model.exr"));
  double err = 0, norm = 0;
  for (size_t i = 0; i < alone.size(); ++i)
    err += std::pow(fromModel[i] - alone[i], 2), norm += std::pow(alone[i], 2);
  EXPECT_LT(std::sqrt(err / norm), 0.05);

  // A light path: every map under each line's lights, in line order.
  {
    std::ofstream path(out.file("path.txt"));
    path << "# a lamp moving past the sphere\npoint:-2,2,2,30\n\npoint:0,2.5,2,30 ; "
            "sphere:2,1,1.5,0.2,50\npoint:2,2,2,30\n";
  }
  const RunResult moving = runCli(relight + "--env sky --light-path " + out.file("path.txt") +
                                  " --light point:0,-3,2,5 --out " + out.file("moving"));
  ASSERT_EQ(moving.status, 0) << moving.output;
  const std::string movingManifest = test::readFile(out.file("moving/manifest.csv"));
  EXPECT_NE(movingManifest.find("\"point:0,2.5,2,30;sphere:2,1,1.5,0.2,50;point:0,-3,2,5\""),
            std::string::npos)
      << movingManifest;
  ASSERT_EQ(runCli(relight +
                   "--env sky --light point:0,2.5,2,30 --light sphere:2,1,1.5,0.2,50 "
                   "--light point:0,-3,2,5 --out " +
                   out.file("second.exr"))
                .status,
            0);
  // A transport's batch shares one product over its frames: equal to rounding.
  EXPECT_LT(maxDifference(test::readPixels(out.file("moving/00001_sky_y0_l0001.exr")),
                          test::readPixels(out.file("second.exr"))),
            1e-6 * peak);
  EXPECT_TRUE(test::fs::exists(out.file("moving/00002_sky_y0_l0002.exr")));
  // A sweep: a frame per value of the swept number, crossed with the path's
  // lines (line major), the frame named by its light set.
  const RunResult swept = runCli(relight + "--light-path " + out.file("path.txt") +
                                 " --light point:0,-3,1:2.5:0.5,5 --out " + out.file("swept"));
  ASSERT_EQ(swept.status, 0) << swept.output;
  const std::string sweptManifest = test::readFile(out.file("swept/manifest.csv"));
  const size_t frame5 = sweptManifest.find("00005_lights_y0_l0005.exr");
  ASSERT_NE(frame5, std::string::npos) << sweptManifest;
  const std::string line5 = sweptManifest.substr(sweptManifest.rfind('\n', frame5));
  EXPECT_NE(line5.find("\"point:0,2.5,2,30;sphere:2,1,1.5,0.2,50;point:0,-3,2,5\","),
            std::string::npos)
      << sweptManifest;
  EXPECT_TRUE(test::fs::exists(out.file("swept/00008_lights_y0_l0008.exr")));
  EXPECT_FALSE(test::fs::exists(out.file("swept/00009_lights_y0_l0009.exr")))
      << "3 lines x 3 values";
  expectFailure(relight + "--light point:0,-3,2:1:0.5,5 --out " + out.file("z"),
                "'2:1:0.5': the end must exceed the start");
  EXPECT_FALSE(test::fs::exists(out.file("z")));
  {
    std::ofstream path(out.file("bad-path.txt"));
    path << "point:0,2,2,1\npoint:0,2\n";
  }
  expectFailure(relight + "--light-path " + out.file("bad-path.txt") + " --out " + out.file("y"),
                "bad-path.txt:2: light 'point:0,2': has 2 numbers");
  EXPECT_FALSE(test::fs::exists(out.file("y")));

  expectFailure(relight + "--light point:1,2 --out " + out.file("x.exr"),
                "--light 'point:1,2': has 2 numbers; write point:X,Y,Z,I");
  expectFailure(relight + "--light sphere:0,0,0,1.5,1 --out " + out.file("x.exr"),
                "--light 'sphere:0,0,0,1.5,1': encloses");
  expectFailure(relight + "--light point:0,3,0,1 --rotate 0:360:90 --out " + out.file("x"),
                "rotates environments");
  expectFailure("relight " + transport_ + " --out " + out.file("x.exr"),
                "give at least one lighting (or a local light)");
  EXPECT_FALSE(test::fs::exists(out.file("x.exr")));
}

TEST_F(Cli, RelightAModelInBatchTimingModeAndWithFewerRanks) {
  TempDir out;
  const std::string model = out.file("m.h5");
  ASSERT_EQ(runCli("compress " + transport_ + " --method adaptive-quad --coeffs f16 --bases f16 " +
                   "--quiet --out " + model)
                .status,
            0);
  const std::string relight = "relight " + model + " --quiet --exr-float ";
  // A batch of 2 maps x 3 rotations equals the same frames one at a time.
  const RunResult batch =
      runCli(relight + "--env sky --env constant:1 --rotate 0:360:120 --out " + out.file("batch"));
  ASSERT_EQ(batch.status, 0) << batch.output;
  std::ifstream manifest(out.file("batch/manifest.csv"));
  int lines = 0;
  for (std::string line; std::getline(manifest, line);) ++lines;
  EXPECT_EQ(lines, 1 + 6);
  // manifest.jsonl: the same frames, each with its lighting labels. A
  // constant map has only band 0, 2 sqrt(pi) for radiance 1; turning the sky
  // about +Y keeps its band 0 and its vertical band-1 term (1,-1), within
  // the binning of this transport's coarse lattice (3% measured).
  std::ifstream jsonLines(out.file("batch/manifest.jsonl"));
  std::vector<nlohmann::json> rows;
  for (std::string line; std::getline(jsonLines, line);)
    rows.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(rows.size(), 6u);
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    EXPECT_EQ(row["frame"].get<size_t>(), i);
    EXPECT_EQ(row["env"], i < 3 ? "sky" : "constant:1");
    EXPECT_EQ(row["yaw"].get<double>(), 120.0 * (i % 3));
    EXPECT_TRUE(test::fs::exists(out.path() / "batch" / row["outputs"][0].get<std::string>()))
        << row.dump();
    const auto& sh9 = row["sh9"];
    ASSERT_EQ(sh9.size(), 9u);
    const auto& first = rows[i < 3 ? 0 : 3]["sh9"];
    for (int c = 0; c < 3; ++c) {
      if (i >= 3) {
        EXPECT_NEAR(sh9[0][c].get<double>(), 2 * std::sqrt(M_PI), 1e-12);
        for (int b = 1; b < 9; ++b) EXPECT_NEAR(sh9[b][c].get<double>(), 0, 1e-12);
      }
      EXPECT_NEAR(sh9[0][c].get<double>(), first[0][c].get<double>(),
                  1e-3 * first[0][c].get<double>());
      EXPECT_NEAR(sh9[1][c].get<double>(), first[1][c].get<double>(),
                  5e-2 * std::abs(first[1][c].get<double>()) + 1e-9);
    }
  }
  ASSERT_EQ(runCli(relight + "--env sky --rotate 120 --out " + out.file("one.exr")).status, 0);
  EXPECT_EQ(maxDifference(test::readPixels(out.file("one.exr")),
                          test::readPixels(out.file("batch/00001_sky_y120.exr"))),
            0.0);
  // One thread gives the same image; a full turn gives the unrotated one.
  ASSERT_EQ(
      runCli(relight + "--env sky --rotate 120 --threads 1 --out " + out.file("t1.exr")).status, 0);
  EXPECT_EQ(
      maxDifference(test::readPixels(out.file("t1.exr")), test::readPixels(out.file("one.exr"))),
      0.0);
  ASSERT_EQ(runCli(relight + "--env sky --rotate 360 --out " + out.file("turn.exr")).status, 0);
  const auto unrotated = test::readPixels(out.file("batch/00000_sky_y0.exr"));
  double peak = 0;
  for (float v : unrotated) peak = std::max(peak, double(v));
  EXPECT_LT(maxDifference(test::readPixels(out.file("turn.exr")), unrotated), 1e-5 * peak);

  // Timing mode reports what cli.md promises.
  const RunResult timed = runCli(relight + "--env sky --frames 3 --out " + out.file("t.exr") +
                                 " --json " + out.file("t.json"));
  ASSERT_EQ(timed.status, 0) << timed.output;
  const auto t = nlohmann::json::parse(std::ifstream(out.file("t.json")));
  EXPECT_EQ(t["timed_frames"].get<int>(), 3);
  for (const char* key : {"ms_per_frame_median", "ms_per_frame_min", "ms_per_frame_max",
                          "bytes_per_frame", "gb_per_s"})
    EXPECT_GT(t[key].get<double>(), 0) << key;
  EXPECT_EQ(t["method"], "adaptive-quad");

  // A batch says where its time went: stages on the relighting thread fit in
  // the wall time, writing ran beside them, and frames / wall is the rate.
  const RunResult staged = runCli(relight + "--env sky --env constant:1 --rotate 0:360:60 --out " +
                                  out.file("staged") + " --json " + out.file("s.json"));
  ASSERT_EQ(staged.status, 0) << staged.output;
  const auto stages = nlohmann::json::parse(std::ifstream(out.file("s.json")));
  const auto seconds = [&](const char* stage) {
    return stages["stages"][stage]["seconds"].get<double>();
  };
  const double wall = seconds("wall");
  double onRelightThread = 0;
  for (const char* stage : {"open", "lighting", "projection", "shading", "sources", "background",
                            "waiting_for_writing"}) {
    EXPECT_GE(seconds(stage), 0) << stage;
    onRelightThread += seconds(stage);
  }
  EXPECT_GT(seconds("shading"), 0);
  EXPECT_GT(seconds("writing"), 0);
  EXPECT_LE(onRelightThread, wall * 1.001);
  EXPECT_NEAR(stages["frames_per_second"].get<double>() * wall, 12, 1e-6);
  EXPECT_NEAR(stages["stages"]["shading"]["share_of_wall"].get<double>(), seconds("shading") / wall,
              1e-9);
  // The sky's sun, split off and lit exactly by shadow rays, frame by frame.
  EXPECT_GT(seconds("sources"), 0);
  EXPECT_TRUE(stages.contains("lamp_shadow_rays"));
  // Its own rays, part of the lamps' total: a probe per camera sample that
  // faces it, and strata where a penumbra may fall.
  const nlohmann::json& sunRays = stages.at("source_shadow_rays");
  EXPECT_GT(sunRays["total"].get<long long>(), 0);
  EXPECT_LE(sunRays["total"].get<long long>(),
            stages["lamp_shadow_rays"]["total"].get<long long>());
  const Model sunlit = readModel(model);
  const double samplesPerRow =
      double(sunlit.geometry.lamps.samples()) / double(sunlit.geometry.rows());
  EXPECT_GT(sunRays["per_source_per_covered_pixel"].get<double>(), 0);
  EXPECT_LE(sunRays["per_source_per_covered_pixel"].get<double>(),
            (1 + 64) * samplesPerRow);  // --lamp-rays 64, the default
  // A lamp's shadow rays: at most one per traced camera sample for a point lamp.
  ASSERT_EQ(runCli(relight + "--light point:0.3,3,2,20 --background black --out " +
                   out.file("lamp.exr") + " --json " + out.file("lamp.json"))
                .status,
            0);
  const auto lamp = nlohmann::json::parse(std::ifstream(out.file("lamp.json")));
  ASSERT_TRUE(lamp.contains("lamp_shadow_rays")) << lamp.dump();
  EXPECT_GT(lamp["lamp_shadow_rays"]["total"].get<long long>(), 0);
  const double perPixel = lamp["lamp_shadow_rays"]["per_covered_pixel"].get<double>();
  EXPECT_GT(perPixel, 0);
  const Model m = readModel(model);
  EXPECT_LE(perPixel, double(m.geometry.lamps.samples()) / double(m.geometry.rows()));

  // No bases (and no means in this model): every object pixel is black, while
  // the background still shows the environment.
  ASSERT_EQ(runCli(relight + "--env constant:1 --background black --max-rank 0 --out " +
                   out.file("r0.exr"))
                .status,
            0);
  for (float v : test::readPixels(out.file("r0.exr"))) EXPECT_EQ(v, 0.0f);
  EXPECT_EQ(runCli(relight + "--env sky --max-rank 50% --out " + out.file("r50.exr")).status, 0);
  expectFailure(relight + "--env sky --max-rank -1 --out " + out.file("x.exr"), "--max-rank");
  expectFailure(relight + "--env sky --max-rank many --out " + out.file("x.exr"), "many");
  expectFailure("relight " + transport_ + " --env sky --max-rank 3 --out " + out.file("x.exr"),
                "transport file");

  // A truncated model file is named, and nothing is written.
  {
    std::ifstream in(model, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(out.file("cut.h5"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  expectFailure("relight " + out.file("cut.h5") + " --env sky --out " + out.file("x.exr"),
                "cut.h5");
  EXPECT_FALSE(test::fs::exists(out.file("x.exr")));
}

TEST_F(Cli, EveryCommandHasHelp) {
  for (const char* cmd :
       {"precompute", "compress", "relight", "envmap", "info", "scenes", "bench rays",
        "bench methods", "bench relight", "bench batch", "bench codecs"}) {
    const RunResult r = runCli(std::string(cmd) + " --help");
    EXPECT_EQ(r.status, 0) << cmd;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << cmd;
  }
}

// Blender's sunrise sky (blender-data): its low sun holds most of its light.
const std::string kSunrise = "/usr/share/blender/datafiles/studiolights/world/sunrise.exr";

/// `envmap` of the sunrise sky with `flags`: its --json report.
nlohmann::json envmapReport(const test::TempDir& out, const std::string& flags) {
  const RunResult r = runCli("envmap " + kSunrise + " --size 64x32 --quiet --out " +
                             out.file("e.exr") + " --json " + out.file("e.json") + flags);
  EXPECT_EQ(r.status, 0) << r.output;
  return nlohmann::json::parse(std::ifstream(out.file("e.json")));
}

TEST(EnvmapSources, ARealSkysSunIsListedTurnedWithTheMapAndOffListsNone) {
  const std::string& map = kSunrise;
  test::TempDir out;
  const auto sources = [&](const std::string& flags) {
    return envmapReport(out, flags)["sources"];
  };
  const auto found = sources("");
  ASSERT_EQ(found.size(), 1u) << found.dump();
  const double theta = found[0]["theta_deg"], phi = found[0]["phi_deg"];
  EXPECT_GT(found[0]["energy_share"].get<double>(), 0.3);
  EXPECT_LT(found[0]["radius_deg"].get<double>(), 4);
  EXPECT_GT(theta, 60);  // low in the sky
  EXPECT_LT(theta, 90);
  // A yaw of 90 degrees turns +X (PHI 90) to -Z (PHI 0): PHI falls by 90.
  const auto turned = sources(" --rotate 90");
  ASSERT_EQ(turned.size(), 1u);
  EXPECT_NEAR(turned[0]["theta_deg"].get<double>(), theta, 1e-9);
  EXPECT_NEAR(std::remainder(turned[0]["phi_deg"].get<double>() - (phi - 90), 360.0), 0, 1e-9);
  EXPECT_TRUE(sources(" --sun off").empty());
  expectFailure("envmap " + map + " --sun maybe --out " + out.file("x.exr"), "--sun 'maybe'");
}

TEST(EnvmapSources, WithoutSourcesTheMapLeftAndItsSourcesHoldTheWholeMapsEnergy) {
  // Sources plus the map left hold the map's energy (docs/lighting.md, "A
  // map's sources"); the sun's is its radiance x 2 pi (1 - cos(radius)).
  const std::string& map = kSunrise;
  test::TempDir out;
  const nlohmann::json whole = envmapReport(out, ""),
                       rest = envmapReport(out, " --without-sources");
  EXPECT_FALSE(whole["without_sources"].get<bool>());
  EXPECT_TRUE(rest["without_sources"].get<bool>());
  ASSERT_EQ(rest["sources"].size(), 1u);
  const nlohmann::json& sun = rest["sources"][0];
  const double radius = sun["radius_deg"].get<double>() * std::numbers::pi / 180;
  const double solidAngle = 2 * std::numbers::pi * (1 - std::cos(radius));
  for (int c = 0; c < 3; ++c) {
    const double sunEnergy = sun["radiance"][c].get<double>() * solidAngle;
    const double total = whole["energy"][c].get<double>();
    EXPECT_GT(sunEnergy, 0.3 * total);  // the sunrise's sun holds most of it
    EXPECT_NEAR(rest["energy"][c].get<double>() + sunEnergy, total, 1e-5 * total) << c;
  }
  expectFailure("envmap " + map + " --sun off --without-sources --out " + out.file("x.exr"),
                "--without-sources");
}

}  // namespace
}  // namespace acpca
