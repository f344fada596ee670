// Datasets a training pipeline can trust, through the real CLI: every frame
// its own file whatever its lighting is called, no negative light unless
// asked for, and maps or light sets that cannot mean what they seem refused.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "tests/cli/image_pixels.h"
#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// A lat-long map of width x height, `value` everywhere but a bright patch
/// whose place depends on `patch` (so two maps relight differently).
void writeMap(const std::string& path, float value, int patch, int width = 16, int height = 8) {
  std::vector<float> rgb(static_cast<size_t>(width) * height * 3, value);
  for (int c = 0; c < 3; ++c) rgb[3 * (2 * width + patch) + c] = 50;
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) && out->close());
}

std::vector<json> manifestLines(const std::string& directory) {
  std::vector<json> lines;
  std::ifstream in(directory + "/manifest.jsonl");
  for (std::string line; std::getline(in, line);) lines.push_back(json::parse(line));
  return lines;
}

class Dataset : public ::testing::Test {
 protected:
  /// Relights `inputs` under `lightings` into DIR and checks what a loader
  /// relies on: as many frame files as manifest rows, each listed once, each
  /// the very image of its row's lighting (relit alone, pixel for pixel).
  void expectEveryFrameItsOwnFile(const std::string& inputs, const std::string& lightings,
                                  size_t frames) {
    const std::string out = dir_.file("set");
    fs::remove_all(out);
    const RunResult r =
        runCli("relight " + inputs + lightings + " --exr-float --quiet --out " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    const std::vector<json> lines = manifestLines(out);
    ASSERT_EQ(lines.size(), frames);
    size_t images = 0;
    for (const auto& entry : fs::directory_iterator(out))
      images += entry.path().extension() == ".exr";
    EXPECT_EQ(images, frames) << "a frame's file went missing or was written over";
    std::set<std::string> names;
    for (size_t i = 0; i < lines.size(); ++i) {
      const json& line = lines[i];
      ASSERT_EQ(line["outputs"].size(), 1u);
      const std::string name = line["outputs"][0];
      EXPECT_TRUE(names.insert(name).second) << name << " listed twice";
      EXPECT_EQ(name.substr(0, 6), concat(std::setw(5), std::setfill('0'), i, "_")) << name;
      EXPECT_EQ(name.find('/'), std::string::npos) << "relative to the dataset: " << name;
      const std::string alone = dir_.file("alone.exr");
      const RunResult one = runCli("relight " + line["input"].get<std::string>() + " --env " +
                                   line["env"].get<std::string>() + " --rotate " +
                                   line["yaw"].dump() + " --exr-float --quiet --out " + alone);
      ASSERT_EQ(one.status, 0) << one.output;
      // A batch's frames share one pass over T: equal to float rounding.
      EXPECT_LT(relativeDifference(test::readPixels(out + "/" + name), test::readPixels(alone)),
                1e-6)
          << name << " is not its lighting's";
    }
  }

  static double relativeDifference(const std::vector<float>& a, const std::vector<float>& b) {
    if (a.size() != b.size() || a.empty()) return INFINITY;
    double most = 0, peak = 0;
    for (size_t i = 0; i < a.size(); ++i)
      most = std::max(most, std::abs(double(a[i]) - b[i])), peak = std::max(peak, double(b[i]));
    return most / peak;
  }

  test::TempDir dir_;
  const std::string plant_ = test::fixture("small-plant");
};

TEST_F(Dataset, EveryFrameHasItsOwnFileWhateverItsLightingIsCalled) {
  // Two folders that each hold an x.exr.
  fs::create_directories(dir_.file("a"));
  fs::create_directories(dir_.file("b"));
  writeMap(dir_.file("a/x.exr"), 0.5f, 3);
  writeMap(dir_.file("b/x.exr"), 1.5f, 11);
  const std::string folders = " --env " + dir_.file("a") + " --env " + dir_.file("b");
  expectEveryFrameItsOwnFile(plant_, folders, 2);
  EXPECT_GT(relativeDifference(test::readPixels(dir_.file("set/00000_x_y0.exr")),
                               test::readPixels(dir_.file("set/00001_x_y0.exr"))),
            0.1)
      << "the two maps should light the plant apart";
  // Two suns equal to the six digits a name keeps, a repeated --env, and
  // yaws equal to the name's rounding.
  expectEveryFrameItsOwnFile(plant_, " --env sun:10.141811,90,2,1000 --env sun:10.141822,90,2,1000",
                             2);
  expectEveryFrameItsOwnFile(plant_, " --env sky --env sky", 2);
  expectEveryFrameItsOwnFile(plant_, " --env sky --rotate 10.00001 --rotate 10.00002", 2);
  // Views x maps: the views' frames numbered on, across the batch.
  fs::copy_file(plant_, dir_.file("v0.h5"));
  fs::copy_file(plant_, dir_.file("v1.h5"));
  expectEveryFrameItsOwnFile(dir_.file("v0.h5") + " " + dir_.file("v1.h5"), folders, 4);
}

TEST_F(Dataset, ManifestsNameFilesRelativeToTheDatasetSoItCanMove) {
  const std::string batch = " --env sky --rotate 0:360:180 --aov all --lighting-exr --quiet --out ";
  ASSERT_EQ(runCli("relight " + plant_ + batch + dir_.file("here")).status, 0);
  // The same batch from another working directory, under another name.
  fs::create_directories(dir_.file("elsewhere"));
  ASSERT_EQ(runShell("cd " + dir_.file("elsewhere") + " && " + ACPCA_CLI_PATH + " relight " +
                     plant_ + batch + "../there")
                .status,
            0);
  for (const char* manifest : {"manifest.csv", "manifest.jsonl"})
    EXPECT_EQ(test::readFile(dir_.file("here/") + manifest),
              test::readFile(dir_.file("there/") + manifest))
        << manifest;
  for (const json& line : manifestLines(dir_.file("here")))
    for (const char* key : {"outputs", "labels", "shading", "lighting"})
      for (const auto& path : line[key]) {
        EXPECT_EQ(path.get<std::string>().find('/'), std::string::npos) << path;
        EXPECT_TRUE(fs::exists(dir_.file("here/" + path.get<std::string>()))) << path;
      }
}

/// Every colour value of an image file below zero: how many, and the lowest.
std::pair<long long, float> negativesOf(const std::string& path) {
  const std::vector<float> pixels = test::readPixels(path);
  long long count = 0;
  float lowest = 0;
  for (float v : pixels)
    if (v < 0) ++count, lowest = std::min(lowest, v);
  return {count, lowest};
}

TEST_F(Dataset, FramesCarryNoNegativeLightUnlessAskedTo) {
  // A lamp through the lattice reads single entries of a model's
  // reconstruction of T, which undershoots where the transport is zero or
  // small (a lamp lit exactly never goes below zero).
  const std::string model = dir_.file("m.h5");
  ASSERT_EQ(runCli("compress " + plant_ + " --method adaptive-quad --quiet --out " + model).status,
            0);
  const std::string lamp = "relight " + model +
                           " --light point:0,3,2,40 --light-mode lattice --background black "
                           "--aov shading "
                           "--exr-float --quiet --json ";
  ASSERT_EQ(runCli(lamp + dir_.file("raw.json") + " --keep-negative --out " + dir_.file("raw.exr"))
                .status,
            0);
  const auto [rawCount, rawLowest] = negativesOf(dir_.file("raw.exr"));
  ASSERT_GT(rawCount, 0) << "this lamp no longer shows the model's undershoot";
  const json raw = json::parse(test::readFile(dir_.file("raw.json")));
  EXPECT_EQ(raw["outputs"][0]["negative_values"].get<long long>(), rawCount);
  EXPECT_EQ(raw["outputs"][0]["most_negative"].get<float>(), rawLowest);
  EXPECT_FALSE(raw["negative"]["clamped"].get<bool>());
  EXPECT_GT(negativesOf(dir_.file("raw_shading.exr")).first, 0);

  ASSERT_EQ(runCli(lamp + dir_.file("clamped.json") + " --out " + dir_.file("clamped.exr")).status,
            0);
  EXPECT_EQ(negativesOf(dir_.file("clamped.exr")).first, 0);
  EXPECT_EQ(negativesOf(dir_.file("clamped_shading.exr")).first, 0);
  const json clamped = json::parse(test::readFile(dir_.file("clamped.json")));
  EXPECT_EQ(clamped["outputs"][0]["negative_values"].get<long long>(), rawCount);
  EXPECT_TRUE(clamped["negative"]["clamped"].get<bool>());
  EXPECT_EQ(clamped["negative"]["frames"].get<long long>(), 1);
  // The clamp changes those values alone: max(raw, 0), value for value.
  const std::vector<float> before = test::readPixels(dir_.file("raw.exr")),
                           after = test::readPixels(dir_.file("clamped.exr"));
  ASSERT_EQ(before.size(), after.size());
  for (size_t i = 0; i < before.size(); ++i) ASSERT_EQ(after[i], std::max(before[i], 0.0f)) << i;
}

TEST_F(Dataset, AMapOfNeitherLatLongNorCubeCrossAspectIsRefused) {
  for (const auto& [width, height] : {std::pair{24, 8}, std::pair{32, 8}}) {
    const std::string map = dir_.file(concat("wide", width, ".exr"));
    writeMap(map, 1, 3, width, height);
    expectFailure("relight " + plant_ + " --env " + map + " --out " + dir_.file("x.exr"),
                  concat(map, ": a ", width, "x", height,
                         " image is neither a lat-long map (2:1) nor a horizontal cube cross"));
    EXPECT_FALSE(fs::exists(dir_.file("x.exr")));
  }
  // A pixel off 2:1 reads, with a warning naming the file and its size.
  const std::string near = dir_.file("near.exr");
  writeMap(near, 1, 3, 201, 100);
  const RunResult r =
      runCli("relight " + plant_ + " --env " + near + " --out " + dir_.file("near-relit.exr"));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(near + ": 201x100 is not quite 2:1"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace acpca
