// Scenes of several views end to end: precompute and build write a file per
// view with that view's camera, a view that sees nothing is refused before
// any is rendered, and relight takes the views as one batch whose frames
// equal each view relit alone.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/cli/image_pixels.h"
#include "tests/cli/run_cli.h"
#include "tests/cli/sphere_floor_scene.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;

std::string writeScene(const TempDir& dir, const std::string& name, const std::string& cameras) {
  std::ofstream(dir.file(name)) << "{\"cameras\": " << cameras << ", "
                                << test::kSphereOnFloorObjects << "}";
  return dir.file(name);
}

TEST(Views, AnOrbitIsAFilePerViewAndRelitAsOneBatch) {
  TempDir dir;
  const std::string scene = writeScene(dir, "orbit.json", R"({"orbit": {"target": [0, 0.5, 0],
      "radius": 5, "elevation_deg": 20, "count": 3, "fov": 30, "width": 24, "height": 16}})");
  const RunResult r = runCli("precompute --scene " + scene + " --cubemap 4 --spp 1 --quiet --out " +
                             dir.file("t.h5"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(test::fs::exists(dir.file("t.h5")));
  std::vector<std::string> views;
  for (int k = 0; k < 3; ++k) {
    views.push_back(dir.file("t_v0" + std::to_string(k) + ".h5"));
    const RunResult info = runCli("info " + views.back() + " --json -");
    ASSERT_EQ(info.status, 0) << info.output;
    const auto eye = nlohmann::json::parse(info.output)["camera"]["eye"];
    // Azimuth 120 k degrees from +Z toward +X, 20 degrees up, 5 away.
    const double azimuth = 2.0944 * k, flat = 5 * std::cos(0.349066);
    EXPECT_NEAR(eye[0].get<double>(), flat * std::sin(azimuth), 1e-3) << k;
    EXPECT_NEAR(eye[1].get<double>(), 0.5 + 5 * std::sin(0.349066), 1e-3) << k;
    EXPECT_NEAR(eye[2].get<double>(), flat * std::cos(azimuth), 1e-3) << k;
  }
  const std::string batch = " --env sky --rotate 0:90:45 --aov mask --quiet --out ";
  ASSERT_EQ(
      runCli("relight " + views[0] + " " + views[1] + " " + views[2] + batch + dir.file("set"))
          .status,
      0);
  // Frames numbered across the views: view k's i-th is 2k + i.
  for (const char* name :
       {"00000_v00_sky_y0.exr", "00005_v02_sky_y45.exr", "labels_v00.exr", "labels_v02.exr"})
    EXPECT_TRUE(test::fs::exists(dir.file(std::string("set/") + name))) << name;
  const std::string csv = test::readFile(dir.file("set/manifest.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "view,input,env,yaw,pitch,roll,exposure,lights,output");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 7);
  // View 1 alone gives the same frame.
  ASSERT_EQ(runCli("relight " + views[1] + batch + dir.file("one")).status, 0);
  const std::vector<float> alone = test::readPixels(dir.file("one/00001_sky_y45.exr"));
  EXPECT_FALSE(alone.empty());
  EXPECT_EQ(test::readPixels(dir.file("set/00003_v01_sky_y45.exr")), alone);
  EXPECT_EQ(test::readPixels(dir.file("set/labels_v01.exr")),
            test::readPixels(dir.file("one/labels.exr")));
  // build: a model per view.
  ASSERT_EQ(
      runCli("build --scene " + scene + " --cubemap 4 --spp 1 --quiet --out " + dir.file("m.h5"))
          .status,
      0);
  for (const char* name : {"m_v00.h5", "m_v01.h5", "m_v02.h5"})
    EXPECT_TRUE(test::fs::exists(dir.file(name))) << name;
}

TEST(Views, AViewThatSeesNothingIsRefusedBeforeAnyIsWritten) {
  TempDir dir;
  const std::string scene = writeScene(dir, "away.json", R"([
      {"eye": [0, 1, 5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 30, "width": 16, "height": 16},
      {"eye": [0, 1, 5], "target": [0, 1, 10], "up": [0, 1, 0], "fov": 10, "width": 16, "height": 16}])");
  for (const char* command : {"precompute", "build"}) {
    expectFailure(
        std::string(command) + " --scene " + scene + " --cubemap 4 --out " + dir.file("t.h5"),
        "view 1 (camera at 0,1,5 toward 0,1,10) sees nothing");
    EXPECT_FALSE(test::fs::exists(dir.file("t_v00.h5"))) << command;
  }
}

}  // namespace
}  // namespace acpca
